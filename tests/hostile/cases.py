"""A corpus of hostile and broken inputs for the command line and the Python/Gymnasium API.

Each :class:`Case` writes the files it needs into a fresh directory (``make(tmp)``) and returns
its invocation: a list of CLI arguments (after ``jointattention``) or Python source text (an
API call, run with ``exec``). The same cases run in two harnesses:

- ``scripts/hostile_corpus.py`` runs each in its own subprocess against any source tree and
  prints how many ended in each outcome;
- ``tests/test_hostile.py`` runs each in-process and asserts that it ended cleanly.

Outcomes (:data:`OUTCOMES`): ``clean`` (the refusal we want: exit status 2, one
``error:`` line, no traceback, the directory untouched; for the API a one-line
``JointAttentionError`` naming the argument), ``ok`` (an expected success whose ``check``
passed), ``traceback``, ``accepted`` (bad input taken), ``no-bound`` (timed out),
``half-written`` (a clean error, but files were written), ``raw-api`` (the API raised a bare
``TypeError``/``ValueError``/Gymnasium error), and, beyond those: ``unnamed`` (a clean error
line that lacks the required name, or fails the case's check), ``noisy`` (an error line with
other output on stderr), ``refused`` (an error where success was expected), ``check-failed``
(success, but the case's check failed), ``skipped`` and ``setup-failed``.

This module imports nothing of ``jointattention`` at import time (the corpus script measures
other source trees with it); only :func:`run_api` and :func:`api_child_main` import it, in the
process that runs the case.
"""

from __future__ import annotations

import atexit
import contextlib
import functools
import hashlib
import io
import json
import os
import random
import re
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import time
import zipfile
import zlib
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

__all__ = ["CASES", "FAULTS", "OUTCOMES", "Case", "classify_api", "classify_cli",
           "run_api", "run_subprocess", "snapshot"]

TESTS_DIR = Path(__file__).resolve().parents[1]
REPO = TESTS_DIR.parent
SRC = REPO / "src"  # the source tree under test; scripts/hostile_corpus.py --src changes it

FAULTS = ("names", "nonfinite", "validate-first", "corrupt-files", "output-paths",
          "work-bounds", "resume", "opengl", "env-args", "messages", "cli-args",
          "config-types")
OUTCOMES = ("clean", "ok", "traceback", "accepted", "no-bound", "half-written", "raw-api",
            "unnamed", "noisy", "refused", "check-failed", "skipped", "setup-failed")
GOOD = {"error": ("clean",), "ok": ("ok",), "any": ("clean", "ok")}
MARKER = "@@hostile-api-result@@ "

Invocation = list[str] | str


@dataclass(frozen=True)
class Case:
    """One hostile input.

    Attributes:
        id: unique, readable name.
        fault: one of :data:`FAULTS`.
        make: ``make(tmp)`` writes the case's files into ``tmp`` and returns the invocation:
            CLI arguments (a list) or Python source (a str, run with the directory as cwd).
        expect: ``"error"`` (a clean refusal), ``"ok"`` (success and ``check``) or ``"any"``
            (either).
        names: what the error message must contain (case-insensitive; alternatives
            separated by ``|``).
        check: ``check(tmp, text)``: for a success, ``text`` is stdout + stderr (CLI) or
            ``""`` (API); for a refusal, the error output (stderr, or the exception's message).
        env: environment variables for the case (subprocess only).
        subprocess_only: the case needs a fresh process (e.g. ``MUJOCO_GL``).
        skip: returns a reason to skip the case here, or None.
    """

    id: str
    fault: str
    make: Callable[[Path], Invocation]
    expect: str = "error"
    names: str = ""
    check: Callable[[Path, str], bool] | None = None
    env: dict[str, str] | None = None
    subprocess_only: bool = False
    skip: Callable[[], str | None] | None = None

    @property
    def good(self) -> tuple[str, ...]:
        """The outcomes that count as handled."""
        return GOOD[self.expect]


# ---------------------------------------------------------------------------------------------
# Classifying what happened


def snapshot(root: Path) -> dict[str, tuple]:
    """Every path under ``root`` with its kind, size and SHA-256 (symlinks not followed)."""
    out: dict[str, tuple] = {}
    for dirpath, dirnames, filenames in os.walk(root):
        for name in sorted(dirnames + filenames):
            p = Path(dirpath, name)
            rel = p.relative_to(root).as_posix()
            try:
                if p.is_symlink():
                    out[rel] = ("link", os.readlink(p))
                elif p.is_dir():
                    out[rel] = ("dir",)
                elif p.is_file():
                    data = p.read_bytes()
                    out[rel] = ("file", len(data), hashlib.sha256(data).hexdigest())
                else:
                    out[rel] = ("other",)
            except OSError as err:
                out[rel] = ("unreadable", err.errno)
    return out


def _named(case: Case, message: str) -> bool:
    if not case.names:
        return True
    low = message.lower()
    return any(n.lower() in low for n in case.names.split("|"))


def split_stderr(stderr: str) -> tuple[list[str], list[str]]:
    """(lines containing ``error:``, other non-blank lines that are not argparse usage)."""
    errors, others, in_usage = [], [], False
    for line in stderr.splitlines():
        if not line.strip():
            continue
        if "error:" in line:
            errors.append(line)
            in_usage = False
        elif line.startswith("usage:"):
            in_usage = True
        elif in_usage and line[:1].isspace():
            continue
        else:
            others.append(line)
            in_usage = False
    return errors, others


def classify_cli(case: Case, tmp: Path, rc: int, stdout: str, stderr: str, changed: bool,
                 timed_out: bool = False) -> str:
    """The outcome of a CLI case from its exit status, output and the directory's change."""
    if timed_out:
        return "no-bound"
    if "Traceback" in stderr or rc not in (0, 2, 130):
        return "traceback"
    if case.expect == "ok" or (case.expect == "any" and rc == 0):
        if rc != 0:
            return "refused"
        return "ok" if case.check is None or case.check(tmp, stdout + stderr) else "check-failed"
    if rc == 0:
        return "accepted"
    errors, others = split_stderr(stderr)
    if changed:
        return "half-written"
    if rc != 2 or len(errors) != 1 or others:
        return "noisy"
    if not _named(case, errors[0]) or (case.check is not None and not case.check(tmp, stderr)):
        return "unnamed"
    return "clean"


def classify_api(case: Case, tmp: Path, result: dict, changed: bool,
                 timed_out: bool = False) -> str:
    """The outcome of an API case from :func:`run_api`'s result."""
    if timed_out:
        return "no-bound"
    kind = result["kind"]
    if kind == "none":
        if case.expect == "error":
            return "accepted"
        return "ok" if case.check is None or case.check(tmp, "") else "check-failed"
    if kind == "ours":
        if case.expect == "ok":
            return "refused"
        if changed:
            return "half-written"
        message = result["message"].strip()
        if ("\n" in message or not _named(case, message)
                or (case.check is not None and not case.check(tmp, message))):
            return "unnamed"
        return "clean"
    return "raw-api" if kind == "raw" else "traceback"


def run_api(source: str) -> dict:
    """Run API source text; what it raised, as a dict (``kind``: none, ours, raw or other)."""
    try:
        exec(compile(source, "<hostile case>", "exec"), {"__name__": "__hostile__"})
    except BaseException as err:  # every exception is an outcome
        if type(err).__name__ == "HostileTimeout":
            raise
        import traceback

        try:
            from jointattention.errors import JointAttentionError
        except Exception:
            JointAttentionError = ()
        if isinstance(err, JointAttentionError):
            kind = "ours"
        elif (isinstance(err, (TypeError, ValueError))
              or type(err).__module__.startswith("gymnasium")):
            kind = "raw"
        else:
            kind = "other"
        return {"kind": kind, "type": f"{type(err).__module__}.{type(err).__qualname__}",
                "message": str(err), "traceback": traceback.format_exc()}
    return {"kind": "none", "type": "", "message": "", "traceback": ""}


def api_child_main(source: str) -> None:
    """In a subprocess: run ``source`` and print :func:`run_api`'s result after a marker."""
    result = run_api(source)
    sys.stdout.flush()
    print("\n" + MARKER + json.dumps(result), flush=True)


API_CHILD = ("import sys; sys.path.insert(0, {tests!r}); "
             "from hostile.cases import api_child_main; api_child_main(sys.argv[1])")


def child_env(src: Path, case_env: dict[str, str] | None = None) -> dict[str, str]:
    """The environment of a case's subprocess: PYTHONPATH=src, MUJOCO_GL=egl, Agg."""
    env = dict(os.environ)
    env.pop("PYOPENGL_PLATFORM", None)
    env.update({"PYTHONPATH": str(src), "MUJOCO_GL": "egl", "MPLBACKEND": "Agg",
                "PYTHONUNBUFFERED": "1"})
    env.update(case_env or {})
    return env


def _make_removable(root: Path) -> None:
    for dirpath, _, _ in os.walk(root):
        with contextlib.suppress(OSError):
            os.chmod(dirpath, 0o755)


def run_subprocess(case: Case, src: Path, timeout: float) -> dict:
    """Run ``case`` in its own subprocess against the tree ``src``; its outcome and details."""
    start = time.perf_counter()
    reason = case.skip() if case.skip is not None else None
    if reason:
        return {"id": case.id, "fault": case.fault, "outcome": "skipped", "detail": reason,
                "seconds": 0.0}
    tmp = Path(tempfile.mkdtemp(prefix="hostile-"))
    try:
        try:
            invocation = case.make(tmp)
        except Exception as err:
            return {"id": case.id, "fault": case.fault, "outcome": "setup-failed",
                    "detail": f"{type(err).__name__}: {err}", "seconds": 0.0}
        before = snapshot(tmp)
        if isinstance(invocation, str):
            cmd = [sys.executable, "-c", API_CHILD.format(tests=str(TESTS_DIR)), invocation]
        else:
            cmd = [sys.executable, "-m", "jointattention", *invocation]
        proc = subprocess.Popen(cmd, cwd=tmp, env=child_env(src, case.env),
                                stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, start_new_session=True)
        timed_out = False
        try:
            out_b, err_b = proc.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            timed_out = True
            with contextlib.suppress(ProcessLookupError):
                os.killpg(proc.pid, signal.SIGKILL)
            out_b, err_b = proc.communicate()
        out = out_b.decode("utf-8", "replace")
        err = err_b.decode("utf-8", "replace")
        changed = snapshot(tmp) != before
        if isinstance(invocation, str):
            line = next((x for x in reversed(out.splitlines()) if x.startswith(MARKER)), None)
            if timed_out or line is not None:
                result = json.loads(line[len(MARKER):]) if line else {"kind": "none"}
                outcome = classify_api(case, tmp, result, changed, timed_out)
                detail = f"{result.get('type', '')}: {result.get('message', '')}"
            else:
                outcome, detail = "traceback", f"exit {proc.returncode}: {err[-400:]}"
        else:
            outcome = classify_cli(case, tmp, proc.returncode, out, err, changed, timed_out)
            errors, _ = split_stderr(err)
            detail = (f"exit {proc.returncode}; "
                      + (errors[0] if len(errors) == 1 and "Traceback" not in err
                         else err.strip()[-400:]))
        return {"id": case.id, "fault": case.fault, "outcome": outcome, "detail": detail,
                "changed": changed, "seconds": round(time.perf_counter() - start, 2)}
    finally:
        _make_removable(tmp)
        shutil.rmtree(tmp, ignore_errors=True)


# ---------------------------------------------------------------------------------------------
# Writing inputs: configurations, specs, data sets, PNGs and finished run folders


def toml_str(s: str) -> str:
    """``s`` as a TOML basic string (JSON's escapes are TOML's)."""
    return json.dumps(s)


TINY_EXPERIMENT = {"n_steps": "300", "n_seeds": "1", "bin_steps": "100",
                   "n_ceiling_trials": "20"}
TINY_CONDITION = '[[experiment.conditions]]\nname = "n1"\nn_objects = 1\n'


def condition(name: str = "n1", n_objects: int | str = 1, extra: str = "") -> str:
    """One ``[[experiment.conditions]]`` table (``name`` is escaped; ``extra`` raw TOML)."""
    return (f"[[experiment.conditions]]\nname = {toml_str(name)}\nn_objects = {n_objects}\n"
            + (extra + "\n" if extra else ""))


def tiny_toml(*, top: str = "", sections: str = "", experiment: dict | None = None,
              conditions: str | None = None) -> str:
    """A tiny configuration: 300 steps, 1 seed, one 1-object condition, 20 ceiling trials.

    ``top``: top-level keys (raw TOML); ``sections``: more tables (raw TOML);
    ``experiment``: [experiment] keys -> raw TOML values (overriding the tiny ones);
    ``conditions``: the condition tables (raw TOML) instead of the one tiny condition.
    """
    exp = {**TINY_EXPERIMENT, **(experiment or {})}
    lines = "\n".join(f"{k} = {v}" for k, v in exp.items())
    conds = TINY_CONDITION if conditions is None else conditions
    return f"{top}\n\n{sections}\n\n[experiment]\n{lines}\n\n{conds}"


def spec_toml(*, base: str = "tiny.toml", set_: str = "", grid: str = "",
              conditions: str = "", top: str = "") -> str:
    """A sweep spec over ``base`` (a preset, or a file beside the spec).

    ``set_`` and ``grid`` are the raw TOML of those tables; ``conditions`` the condition tables
    (as :func:`condition` writes them, renamed to the spec's ``[[conditions]]``).
    """
    text = f"base = {toml_str(base)}\n{top}\n"
    conditions = conditions.replace("[[experiment.conditions]]", "[[conditions]]")
    if set_:
        text += f"\n[set]\n{set_}\n"
    if grid:
        text += f"\n[grid]\n{grid}\n"
    return text + ("\n" + conditions if conditions else "")


def shipped_datasets_path() -> Path:
    """The shipped data sets of the tree under test."""
    return SRC / "jointattention" / "data" / "caregiver_125.npz"


@functools.cache
def _shipped_arrays() -> dict[str, np.ndarray]:
    with np.load(shipped_datasets_path(), allow_pickle=False) as z:
        return {k: z[k] for k in z.files}


def small_arrays(n: int = 5, offset: int = 0) -> dict[str, np.ndarray]:
    """The arrays of ``n`` of the shipped data sets (rows ``offset`` on)."""
    out = {}
    for k, v in _shipped_arrays().items():
        out[k] = v[offset:offset + n].copy() if v.ndim and len(v) > 1 else v.copy()
    return out


def npz_bytes(arrays: dict, *, compressed: bool = True, pickle: bool = False) -> bytes:
    """An ``.npz`` archive of ``arrays`` as bytes."""
    buf = io.BytesIO()
    if compressed and not pickle:
        np.savez_compressed(buf, **arrays)
    else:
        np.savez(buf, **arrays)
    return buf.getvalue()


def small_datasets_bytes(n: int = 5, offset: int = 0, **changes) -> bytes:
    """A valid small data-set file (or one with ``changes`` to its arrays; None drops one)."""
    arrays = small_arrays(n, offset)
    for k, v in changes.items():
        if v is None:
            arrays.pop(k, None)
        else:
            arrays[k] = v
    return npz_bytes(arrays)


def npy_header(descr: str, shape: tuple) -> bytes:
    """A hand-made ``.npy`` version 1.0 header (the array's bytes do not follow)."""
    header = repr({"descr": descr, "fortran_order": False, "shape": shape}).encode("latin1")
    pad = 64 - (10 + len(header) + 1) % 64
    header += b" " * pad + b"\n"
    return b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header


def huge_member_npz() -> bytes:
    """A data-set archive whose ``face`` member's header claims a 1.4 TiB uint8 array."""
    arrays = small_arrays(5)
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_STORED) as z:
        for k, v in arrays.items():
            if k == "face":
                z.writestr("face.npy", npy_header("|u1", (13_000_000, 340, 340)) + b"\0" * 64)
            else:
                member = io.BytesIO()
                np.save(member, v)
                z.writestr(f"{k}.npy", member.getvalue())
    return buf.getvalue()


def _stored_npz(extra: dict[str, bytes]) -> bytes:
    """An uncompressed data-set archive of 5 shipped sets, with ``extra`` members (raw bytes)."""
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_STORED) as z:
        for k, v in small_arrays(5).items():
            z.writestr(f"{k}.npy", npy_bytes(v))
        for name, data in extra.items():
            z.writestr(name, data)
    return buf.getvalue()


def declared_size_npz(n_bytes: int, n_members: int = 1) -> bytes:
    """A data-set archive with ``n_members`` extra members, each declaring ``n_bytes``.

    Its directory makes a bomb's claim without the bomb: each member's data are 64 bytes.
    """
    data = bytearray(_stored_npz({f"bomb{i}.npy": npy_header("|u1", (n_bytes,)) + b"\0" * 64
                                  for i in range(n_members)}))
    at = 0
    while (at := data.find(b"PK\x01\x02", at)) >= 0:  # central directory entries
        name_len = struct.unpack_from("<H", data, at + 28)[0]
        if data[at + 46:at + 46 + name_len].startswith(b"bomb"):
            struct.pack_into("<I", data, at + 24, n_bytes)  # uncompressed size
        at += 46
    return bytes(data)


def many_members_npz(n: int = 2000) -> bytes:
    """A data-set archive with ``n`` extra one-byte members."""
    return _stored_npz({f"x{i}.npy": npy_bytes(np.zeros(1, np.uint8)) for i in range(n)})


def pickled_member_npz() -> bytes:
    """A data-set archive whose ``face`` member is a pickled object array."""
    arrays = small_arrays(5)
    arrays["face"] = np.array([{"evil": 1}, None, "x"], dtype=object)
    return npz_bytes(arrays, pickle=True)


def bad_crc_npz() -> bytes:
    """A stored (uncompressed) data-set archive with a byte flipped inside ``face``'s data."""
    data = bytearray(npz_bytes(small_arrays(5), compressed=False))
    with zipfile.ZipFile(io.BytesIO(bytes(data))) as z:
        info = z.getinfo("face.npy")
    middle = info.header_offset + 30 + len(info.filename) + 200 + info.file_size // 2
    data[middle] ^= 0xFF
    data[middle + 1] ^= 0xFF
    return bytes(data)


def flipped_deflate_npz() -> bytes:
    """A compressed data-set archive with bytes flipped in the middle of the file."""
    data = bytearray(small_datasets_bytes())
    mid = len(data) // 2
    for i in range(mid, mid + 8):
        data[i] ^= 0x5A
    return bytes(data)


def npy_bytes(array: np.ndarray) -> bytes:
    """A ``.npy`` file's bytes."""
    buf = io.BytesIO()
    np.save(buf, array)
    return buf.getvalue()


def random_bytes(n: int = 4096, seed: int = 1) -> bytes:
    """Deterministic random bytes (no zip or npy magic at the start)."""
    data = bytearray(random.Random(seed).randbytes(n))
    data[:2] = b"\x01\x02"
    return bytes(data)


NOT_UTF8 = b"# caf\xe9 \xff\xfe\n[model]\nlearning_rate = 0.0003\n"


def _chunk(kind: bytes, data: bytes) -> bytes:
    return (struct.pack(">I", len(data)) + kind + data
            + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))


def png_bytes(width: int = 64, height: int = 48, *, idat: bytes | None = None) -> bytes:
    """An RGB PNG (a red square on grey), or one whose IHDR claims ``width`` x ``height``."""
    if idat is None:
        rows = []
        for y in range(height):
            row = bytearray(b"\x00")
            for x in range(width):
                inside = width // 4 <= x < width // 2 and height // 4 <= y < height // 2
                row += b"\xff\x00\x00" if inside else b"\x80\x80\x80"
            rows.append(bytes(row))
        idat = zlib.compress(b"".join(rows))
    ihdr = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + _chunk(b"IHDR", ihdr) + _chunk(b"IDAT", idat)
            + _chunk(b"IEND", b""))


def rgb_png(image: np.ndarray) -> bytes:
    """An RGB PNG of ``image`` (H, W, 3) uint8."""
    rows = b"".join(b"\x00" + row.tobytes() for row in np.ascontiguousarray(image, np.uint8))
    ihdr = struct.pack(">IIBBBBB", image.shape[1], image.shape[0], 8, 2, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + _chunk(b"IHDR", ihdr) + _chunk(b"IDAT", zlib.compress(rows))
            + _chunk(b"IEND", b""))


def face_png() -> bytes:
    """A camera image holding the shipped data sets' mean face, 4x larger, on grey.

    The template face finder (its template is that mean face) finds it.
    """
    face = np.rint(_shipped_arrays()["face"].astype(float).mean(axis=0))
    big = np.kron(face, np.ones((4, 4)))
    image = np.full((2 * big.shape[0], 2 * big.shape[1]), face.mean())
    top, left = big.shape[0] // 2, big.shape[1] // 2
    image[top:top + big.shape[0], left:left + big.shape[1]] = big
    return rgb_png(np.repeat(np.clip(image, 0, 255).astype(np.uint8)[..., None], 3, axis=2))


RECORDING = {"rec/recording.csv": "image,pan_rad,tilt_rad,command_pan_rad,command_tilt_rad\n"
                                  "face.png,0.1,0.0,0.05,0.0\n",
             "rec/face.png": face_png}


def huge_png(width: int, height: int) -> bytes:
    """A PNG whose header (with a correct CRC) claims ``width`` x ``height`` pixels."""
    return png_bytes(width, height, idat=zlib.compress(b"\x00" * 256))


def write_files(tmp: Path, files: dict) -> None:
    """Write ``files`` into ``tmp``.

    ``files`` maps a relative path to bytes, text, None (a directory), or a function of no
    arguments that returns one of those.
    """
    for rel, content in files.items():
        if callable(content):
            content = content()
        path = tmp / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        if content is None:
            path.mkdir(exist_ok=True)
        elif isinstance(content, bytes):
            path.write_bytes(content)
        else:
            path.write_text(content, encoding="utf-8")


def files_case(files: dict | Callable[[Path], dict], argv: list[str] | str
               ) -> Callable[[Path], Invocation]:
    """A ``make`` that writes ``files`` and returns ``argv`` (or API source)."""
    def make(tmp: Path) -> Invocation:
        write_files(tmp, files(tmp) if callable(files) else files)
        return list(argv) if isinstance(argv, list) else argv
    return make


# Finished tiny run folders, made once per process by the tree under test and copied per case.

RUN_ARGV = ["reproduce", "--config", "tiny.toml", "--out", "run", "--workers", "1"]
SWEEP_ARGV = ["sweep", "s.toml", "--out", "sw", "--workers", "1"]
_PRISTINE_FILES: dict[str, Callable[[], tuple[dict, list[str]]]] = {
    "run": lambda: ({"tiny.toml": tiny_toml()}, RUN_ARGV),
    "run-ds": lambda: ({"tiny.toml": tiny_toml(top='datasets = "ds.npz"'),
                        "ds.npz": small_datasets_bytes(5)}, RUN_ARGV),
    "sweep-ds": lambda: ({"tiny.toml": tiny_toml(top='datasets = "ds.npz"'),
                          "ds.npz": small_datasets_bytes(5),
                          "s.toml": spec_toml(grid='"model.n_hidden" = [7]')}, SWEEP_ARGV),
}
_CLEANUP: list[Path] = []
atexit.register(lambda: [shutil.rmtree(p, ignore_errors=True) for p in _CLEANUP])


def subprocess_builder(directory: Path, argv: list[str]) -> None:
    """Run ``jointattention argv`` in ``directory`` in a subprocess of the tree :data:`SRC`."""
    proc = subprocess.run([sys.executable, "-m", "jointattention", *argv], cwd=directory,
                          env=child_env(SRC), capture_output=True, text=True, timeout=600)
    if proc.returncode != 0:
        raise RuntimeError(f"building {argv} failed: {proc.stderr[-800:]}")


BUILDER: Callable[[Path, list[str]], None] = subprocess_builder  # the test sets an in-process one


_PRISTINE: dict[str, Path | Exception] = {}


def pristine(kind: str) -> Path:
    """A directory holding a finished tiny run of ``kind`` (made once, then kept).

    A failure to make it is remembered too, and raised again for every case that needs it.
    """
    if kind not in _PRISTINE:
        directory = Path(tempfile.mkdtemp(prefix=f"hostile-{kind}-"))
        _CLEANUP.append(directory)
        files, argv = _PRISTINE_FILES[kind]()
        try:
            write_files(directory, files)
            BUILDER(directory, argv)
            if not (directory / ("sw" if kind.startswith("sweep") else "run")).is_dir():
                raise RuntimeError(f"building the {kind} folder wrote nothing")
            _PRISTINE[kind] = directory
        except Exception as err:
            _PRISTINE[kind] = err
    made = _PRISTINE[kind]
    if isinstance(made, Exception):
        raise RuntimeError(f"the finished {kind} folder could not be made: {made}")
    return made


def copy_pristine(kind: str, tmp: Path) -> None:
    """Copy the finished tiny run of ``kind`` (its configuration and folder) into ``tmp``."""
    shutil.copytree(pristine(kind), tmp, dirs_exist_ok=True, symlinks=True)


@functools.cache
def pristine_cell_keys() -> frozenset[str]:
    """The keys of a finished cell file."""
    with np.load(pristine("run") / "run" / "cells" / "n1__seed000.npz") as z:
        return frozenset(z.files)


def run_case(edit: Callable[[Path], None] | None = None, argv: list[str] | str = RUN_ARGV,
             kind: str = "run") -> Callable[[Path], Invocation]:
    """A ``make`` that copies a finished tiny run, changes it with ``edit``, returns ``argv``."""
    def make(tmp: Path) -> Invocation:
        copy_pristine(kind, tmp)
        if edit is not None:
            edit(tmp)
        return list(argv) if isinstance(argv, list) else argv
    return make


def cell_recomputed(tmp: Path, text: str) -> bool:
    """The cell file was named in the output and is whole again."""
    if "n1__seed000.npz" not in text:
        return False
    try:
        with np.load(tmp / "run" / "cells" / "n1__seed000.npz", allow_pickle=False) as z:
            return frozenset(z.files) == pristine_cell_keys()
    except Exception:
        return False


def ceilings_recomputed(tmp: Path, text: str) -> bool:
    """ceilings.json was named in the output and holds the 1-object ceiling again."""
    try:
        data = json.loads((tmp / "run" / "ceilings.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return False
    return "ceilings.json" in text and isinstance(data, dict) and "1" in data


def run_finished(tmp: Path, text: str) -> bool:
    """The run folder has its claims and a readable timing.json."""
    try:
        json.loads((tmp / "run" / "timing.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return False
    return (tmp / "run" / "claims.md").is_file()


SAFE_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9._=,+-]*")


def safe_point_folders(tmp: Path, text: str) -> bool:
    """A finished sweep in ``out`` whose point folders all have safe names."""
    out = tmp / "out"
    points = [p for p in out.iterdir() if p.is_dir()] if out.is_dir() else []
    return bool(points) and all(SAFE_NAME.fullmatch(p.name) for p in points)


def no_none(tmp: Path, text: str) -> bool:
    """The message does not print ``None`` for an open bound."""
    return "None" not in text


def not_pickled(tmp: Path, text: str) -> bool:
    """The message does not call random bytes pickled."""
    return "pickle" not in text.lower()


def as_root() -> str | None:
    """A skip reason when running as root (root writes into read-only folders)."""
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        return "running as root: a read-only folder is writable"
    return None


# ---------------------------------------------------------------------------------------------
# The cases

CASES: list[Case] = []


def add(case: Case) -> None:
    """Append ``case`` to :data:`CASES`."""
    CASES.append(case)


def _config_argv(command: str) -> list[str]:
    """How each command is given ``c.toml``, cheaply, with an output in ``out``."""
    return {
        "config": ["config", "--config", "c.toml"],
        "reproduce": ["reproduce", "--config", "c.toml", "--out", "out", "--workers", "1"],
        "gaze": ["gaze", "--config", "c.toml", "--condition", "n1", "--out", "out"],
        "render": ["render", "--config", "c.toml", "--out", "out"],
        "datasets-make": ["datasets", "make", "--config", "c.toml", "--n", "1", "--quiet",
                          "out.npz"],
        "parity": ["parity", "--config", "c.toml", "--cases", "1", "--objects", "1",
                   "--out", "out.md"],
        "detect": ["detect", "--config", "c.toml", "--out", "out", "img.png"],
        "sweep": ["sweep", "s.toml", "--out", "out", "--workers", "1"],
    }[command]


def config_case(id: str, fault: str, text: str, command: str = "config", *, names: str = "",
                check: Callable | None = None, expect: str = "error",
                extra: dict | None = None) -> Case:
    """A case that gives ``text`` as ``c.toml`` to ``command`` (see :func:`_config_argv`)."""
    files = {"c.toml": text, **(extra or {})}
    if command == "detect":
        files["img.png"] = png_bytes()
    return Case(id, fault, files_case(files, _config_argv(command)), expect, names, check)


def sweep_case(id: str, fault: str, spec: str, *, names: str = "", base: str | None = None,
               extra: dict | None = None, argv: list[str] | None = None,
               check: Callable | None = None, expect: str = "error") -> Case:
    """A case that runs the sweep ``spec`` (``s.toml``, beside the tiny ``tiny.toml``)."""
    files = {"tiny.toml": tiny_toml() if base is None else base, "s.toml": spec,
             **(extra or {})}
    return Case(id, fault, files_case(files, argv or _config_argv("sweep")), expect, names,
                check)


def api_case(id: str, fault: str, source: str, *, names: str = "",
             files: dict | None = None, expect: str = "error",
             check: Callable | None = None, env: dict | None = None,
             subprocess_only: bool = False, skip: Callable[[], str | None] | None = None) -> Case:
    """A case that runs Python ``source`` (with ``files`` written first)."""
    return Case(id, fault, files_case(files or {}, source), expect, names, check, env,
                subprocess_only, skip)


# 1. Names become paths unchecked ------------------------------------------------------------

BAD_NAMES = {
    "parent-escape": "../../../../escaped",
    "slash": "a/b",
    "backslash": "a\\b",
    "newline": "a\nb",
    "tab": "a\tb",
    "nul": "a\0b",
    "empty": "",
    "long-300": "x" * 300,
    "leading-dot": ".hidden",
    "dot": ".",
    "dotdot": "..",
    "space-only": " ",
    "carriage-return": "a\rb",
}
for _tag, _name in BAD_NAMES.items():
    add(Case(f"reproduce-condition-name-{_tag}", "names",
             files_case({"c.toml": tiny_toml(conditions=condition(_name))},
                        ["reproduce", "--config", "c.toml", "--out", "deep/er/out",
                         "--workers", "1"]),
             names="name"))
add(Case("reproduce-condition-name-absolute", "names",
         lambda tmp: files_case(
             {"c.toml": tiny_toml(conditions=condition(str(tmp / "abs-escaped")))},
             ["reproduce", "--config", "c.toml", "--out", "out", "--workers", "1"])(tmp),
         names="name"))
for _tag in ("parent-escape", "slash", "newline", "empty", "long-300", "nul"):
    add(sweep_case(f"sweep-condition-name-{_tag}", "names",
                   spec_toml(conditions=condition(BAD_NAMES[_tag])), names="name"))
# The data-set files exist where a file of that name can exist, so that the point's name is
# the only fault: refusing it, or running the point in a folder of a safe name, are both
# clean. NUL and 300 characters cannot be file names: those data sets are missing (an error).
for _tag, _value in {"nul": "a\0b.npz", "long-300": "d" * 300}.items():
    add(sweep_case(f"sweep-grid-point-name-{_tag}", "names",
                   spec_toml(grid=f'"datasets" = [{toml_str(_value)}]'),
                   names="datasets|grid|point"))
for _tag, _value in {"newline": "a\nb.npz", "backslash": "..\\..\\x.npz",
                     "carriage-return": "a\rb.npz", "leading-dot": ".x.npz"}.items():
    add(sweep_case(f"sweep-grid-point-name-{_tag}", "names",
                   spec_toml(grid=f'"datasets" = [{toml_str(_value)}]'),
                   names="datasets|grid|point", extra={_value: small_datasets_bytes},
                   expect="any", check=safe_point_folders))
add(sweep_case("sweep-grid-point-name-string-model-kind-escape", "names",
               spec_toml(grid='"model.gate.kind" = ["../../../x"]'),
               names="kind"))
add(config_case("config-condition-name-slash", "names",
                tiny_toml(conditions=condition("x/y")), names="name"))
add(api_case("api-condition-config-name-parent", "names",
             "import jointattention as ja\nja.ConditionConfig(name='../x')", names="name"))
add(api_case("api-condition-config-name-empty", "names",
             "import jointattention as ja\nja.ConditionConfig(name='')", names="name"))

# 2. NaN and inf pass the range checks -------------------------------------------------------

NONFINITE = {
    "learning-rate-nan": ("[model]\nlearning_rate = nan", "model.learning_rate"),
    "fov-deg-nan": ("[world.camera]\nfov_deg = nan", "world.camera.fov_deg"),
    "d-th-fraction-nan": ("[agent]\nd_th_fraction = nan", "agent.d_th_fraction"),
    "momentum-inf": ("[model]\nmomentum = inf", "model.momentum"),
    "init-scale-minus-inf": ("[model]\ninit_scale = -inf", "model.init_scale"),
    "gate-midpoint-inf": ("[model.gate]\nmidpoint_steps = inf", "model.gate.midpoint_steps"),
    "gate-width-nan": ("[model.gate]\nwidth_steps = nan", "model.gate.width_steps"),
    "memory-radius-nan": ("[model.memory]\nradius_deg = nan", "model.memory.radius_deg"),
    "caregiver-distance-inf": ("[world.caregiver]\ndistance_m = inf",
                               "world.caregiver.distance_m"),
    "radius-range-nan": ("[world.objects]\nradius_range_m = [nan, 0.04]",
                         "world.objects.radius_range_m"),
    "interest-weights-inf": ("[agent]\ninterest_weights = [inf, 0.0, 0.0]",
                             "agent.interest_weights"),
    "canny-nan": ("[detector]\ncanny_thresholds = [nan, 150.0]", "detector.canny_thresholds"),
    "vf-gain-nan": ("[agent]\nvf_gain_rad_per_px = nan", "agent.vf_gain_rad_per_px"),
    "lm-step-inf": ("[agent]\nlm_step_deg = inf", "agent.lm_step_deg"),
    "offset-minus-inf": ("[world.camera]\noffset_m = [-inf, 0.06, 0.05]",
                         "world.camera.offset_m"),
    "eye-zoom-nan": ("[world.eye_window]\nzoom = nan", "world.eye_window.zoom"),
}
for _tag, (_section, _name) in NONFINITE.items():
    add(config_case(f"config-{_tag}", "nonfinite", tiny_toml(sections=_section), names=_name))
for _tag in ("learning-rate-nan", "fov-deg-nan", "d-th-fraction-nan", "momentum-inf"):
    _section, _name = NONFINITE[_tag]
    add(config_case(f"reproduce-{_tag}", "nonfinite", tiny_toml(sections=_section),
                    "reproduce", names=_name))
add(config_case("config-eye-window-half-set", "config-types",
                tiny_toml(sections="[world.eye_window]\nwidth_px = 48"), names="eye_window"))
add(config_case("config-condition-model-learning-rate-nan", "nonfinite",
                tiny_toml(conditions=condition("n1", 1, "model = { learning_rate = nan }")),
                names="learning_rate"))
add(config_case("config-condition-gate-rate-nan", "nonfinite",
                tiny_toml(conditions=condition(
                    "n1", 1, 'model = { gate = { kind = "constant", rate = nan } }')),
                names="rate"))
add(config_case("config-condition-gate-midpoint-inf", "nonfinite",
                tiny_toml(conditions=condition(
                    "n1", 1, "model = { gate = { midpoint_steps = inf } }")),
                names="midpoint_steps"))
add(config_case("config-n-steps-inf", "nonfinite",
                tiny_toml(experiment={"n_steps": "inf"}), names="n_steps"))
add(config_case("config-seed-nan", "nonfinite", tiny_toml(top="seed = nan"), names="seed"))
add(sweep_case("sweep-set-learning-rate-nan", "nonfinite",
               spec_toml(set_='"model.learning_rate" = nan'), names="learning_rate"))
add(sweep_case("sweep-set-fov-minus-inf", "nonfinite",
               spec_toml(set_='"world.camera.fov_deg" = -inf'), names="fov_deg"))
add(sweep_case("sweep-grid-learning-rate-nan", "nonfinite",
               spec_toml(grid='"model.learning_rate" = [0.0003, nan]'), names="learning_rate"))
add(sweep_case("sweep-grid-d-th-fraction-inf", "nonfinite",
               spec_toml(grid='"agent.d_th_fraction" = [inf]'), names="d_th_fraction"))
add(sweep_case("sweep-grid-n-steps-inf", "nonfinite",
               spec_toml(grid='"experiment.n_steps" = [inf]'), names="n_steps"))
add(sweep_case("sweep-conditions-model-nan", "nonfinite",
               spec_toml(conditions=condition("n1", 1, "model = { momentum = nan }")),
               names="momentum"))
add(api_case("api-agent-config-d-th-fraction-nan", "nonfinite",
             "import jointattention.config as c\nc.AgentConfig(d_th_fraction=float('nan'))",
             names="d_th_fraction"))
add(api_case("api-measure-ceiling-n-trials-nan", "nonfinite",
             "import jointattention as ja\nja.measure_ceiling(ja.load_config('c.toml'), 1, "
             "float('nan'))", files={"c.toml": tiny_toml()}, names="n_trials"))

# 3. Writing before validating ---------------------------------------------------------------

DUP_CONDITIONS = condition("n1") + "\n" + condition("n1")
for _cmd in ("reproduce", "gaze"):
    add(config_case(f"{_cmd}-datasets-missing", "validate-first",
                    tiny_toml(top='datasets = "missing.npz"'), _cmd, names="missing.npz"))
    add(config_case(f"{_cmd}-datasets-corrupt", "validate-first",
                    tiny_toml(top='datasets = "bad.npz"'), _cmd, names="bad.npz",
                    extra={"bad.npz": random_bytes()}))
add(config_case("reproduce-duplicate-condition-names", "validate-first",
                tiny_toml(conditions=DUP_CONDITIONS), "reproduce", names="n1"))
add(config_case("reproduce-conditions-empty", "validate-first",
                tiny_toml(experiment={"conditions": "[]"}, conditions=""), "reproduce",
                names="conditions"))
add(config_case("reproduce-datasets-is-directory", "validate-first",
                tiny_toml(top='datasets = "dsdir.npz"'), "reproduce", names="dsdir.npz",
                extra={"dsdir.npz": None}))
add(config_case("reproduce-datasets-empty-file", "validate-first",
                tiny_toml(top='datasets = "empty.npz"'), "reproduce", names="empty.npz",
                extra={"empty.npz": b""}))
add(config_case("reproduce-datasets-nan-angles", "validate-first",
                tiny_toml(top='datasets = "nan.npz"'), "reproduce", names="nan.npz",
                extra={"nan.npz": lambda: small_datasets_bytes(
                    theta_face_rad=np.full((5, 2), np.nan))}))
add(sweep_case("sweep-datasets-missing", "validate-first",
               spec_toml(set_='"datasets" = "missing.npz"'), names="missing.npz"))
add(sweep_case("sweep-grid-one-dataset-missing", "validate-first",
               spec_toml(grid='"datasets" = ["ds.npz", "missing.npz"]'), names="missing.npz",
               extra={"ds.npz": small_datasets_bytes}))
add(sweep_case("sweep-datasets-corrupt", "validate-first",
               spec_toml(set_='"datasets" = "bad.npz"'), names="bad.npz",
               extra={"bad.npz": random_bytes()}))
add(sweep_case("sweep-duplicate-condition-names", "validate-first",
               spec_toml(conditions=DUP_CONDITIONS), names="n1"))
add(sweep_case("sweep-conditions-empty", "validate-first",
               spec_toml(top="conditions = []"), names="conditions"))
add(sweep_case("sweep-base-conditions-empty", "validate-first", spec_toml(),
               base=tiny_toml(experiment={"conditions": "[]"}, conditions=""),
               names="conditions"))
add(api_case("api-reproduce-datasets-missing", "validate-first",
             "import jointattention as ja\nja.reproduce(ja.load_config('c.toml'), 'out')",
             files={"c.toml": tiny_toml(top='datasets = "missing.npz"')},
             names="missing.npz"))
add(api_case("api-run-experiment-datasets-corrupt", "validate-first",
             "import jointattention as ja\nja.run_experiment(ja.load_config('c.toml'), 'out')",
             files={"c.toml": tiny_toml(top='datasets = "bad.npz"'),
                    "bad.npz": random_bytes()}, names="bad.npz"))

# 4. Corrupt files: named, or recomputed -----------------------------------------------------

CORRUPT_DATASETS: dict[str, Callable[[], bytes | None]] = {
    "truncated": lambda: small_datasets_bytes()[: len(small_datasets_bytes()) // 2],
    "empty": lambda: b"",
    "bad-crc": bad_crc_npz,
    "flipped-deflate": flipped_deflate_npz,
    "npy-renamed": lambda: npy_bytes(small_arrays()["face"]),
    "random-bytes": random_bytes,
    "huge-member-header": huge_member_npz,
    "member-declares-2gib": lambda: declared_size_npz(2**31 - 1),
    "members-declare-4gib": lambda: declared_size_npz(2**29, 8),
    "2000-members": many_members_npz,
    "pickled-member": pickled_member_npz,
    "text": lambda: b"these are not data sets\n",
    "directory": lambda: None,
    "missing-face": lambda: small_datasets_bytes(face=None),
    "face-float": lambda: small_datasets_bytes(face=np.zeros((5, 25, 30))),
    "angles-inf": lambda: small_datasets_bytes(command_rad=np.full((5, 2), np.inf)),
    "target-1e300": lambda: small_datasets_bytes(target_m=np.full((5, 3), 1e300)),
    "schema-version-2": lambda: small_datasets_bytes(schema_version=np.array(2)),
    "meta-not-json": lambda: small_datasets_bytes(meta=np.array("{not json")),
    "zip-of-nothing": lambda: npz_bytes({}),
    "eyes-float": lambda: small_datasets_bytes(eyes=np.zeros((5, 12, 48))),
    "eyes-too-few": lambda: small_datasets_bytes(eyes=np.zeros((2, 12, 48), np.uint8)),
}
for _tag, _make in CORRUPT_DATASETS.items():
    add(Case(f"datasets-check-{_tag}", "corrupt-files",
             (lambda m: lambda tmp: files_case({"bad.npz": m()},
                                               ["datasets", "check", "bad.npz"])(tmp))(_make),
             names="bad.npz",
             check=not_pickled if _tag in ("random-bytes", "text") else None))
for _tag, _make in CORRUPT_DATASETS.items():  # the same corruptions as a saved model
    add(Case(f"follow-model-{_tag}", "corrupt-files",
             (lambda m: lambda tmp: files_case(
                 {"bad.npz": m(), "img.png": png_bytes()},
                 ["follow", "bad.npz", "img.png", "--out", "out"])(tmp))(_make),
             names="bad.npz",
             check=not_pickled if _tag in ("random-bytes", "text") else None))
for _tag in ("truncated", "empty", "bad-crc", "huge-member-header", "pickled-member",
             "npy-renamed"):
    add(Case(f"api-load-datasets-{_tag}", "corrupt-files",
             (lambda m: lambda tmp: files_case(
                 {"bad.npz": m()},
                 "import jointattention as ja\nja.load_datasets('bad.npz')")(tmp))(
                 CORRUPT_DATASETS[_tag]),
             names="bad.npz"))
for _tag in ("truncated", "bad-crc", "huge-member-header", "pickled-member"):
    add(Case(f"reproduce-datasets-{_tag}", "corrupt-files",
             (lambda m: lambda tmp: files_case(
                 {"c.toml": tiny_toml(top='datasets = "bad.npz"'), "bad.npz": m()},
                 _config_argv("reproduce"))(tmp))(CORRUPT_DATASETS[_tag]),
             names="bad.npz"))



def _special_file(kind: str, argv: Callable[[str], Invocation]) -> Callable[[Path], Invocation]:
    """A ``make`` that gives a device (``/dev/zero``) or a FIFO where a file belongs."""
    def make(tmp: Path) -> Invocation:
        write_files(tmp, {"img.png": png_bytes()})
        if kind == "device":
            return argv("/dev/zero")
        os.mkfifo(tmp / "special.npz")  # reading it would block for ever
        return argv("special.npz")
    return make


for _kind, _name in (("device", "/dev/zero"), ("fifo", "special.npz")):
    add(Case(f"follow-model-{_kind}", "corrupt-files",
             _special_file(_kind, lambda p: ["follow", p, "img.png", "--out", "out"]),
             names=_name))
    add(Case(f"datasets-check-{_kind}", "corrupt-files",
             _special_file(_kind, lambda p: ["datasets", "check", p]), names=_name))
    add(Case(f"api-load-model-{_kind}", "corrupt-files",
             _special_file(_kind, lambda p: f"import jointattention as ja\nja.load_model({p!r})"),
             names=_name))

DEEP = 5000  # levels: beyond Python's recursion limit
for _tag, _text in (("array", "x = " + "[" * DEEP + "]" * DEEP + "\n"),
                    ("inline-table", "x = " + "{a = " * DEEP + "1" + "}" * DEEP + "\n"),
                    ("array-40", "x = " + "[" * 40 + "]" * 40 + "\n")):
    add(config_case(f"config-nested-{_tag}", "corrupt-files", _text, names="c.toml"))
    add(sweep_case(f"sweep-spec-nested-{_tag}", "corrupt-files", _text, names="s.toml"))
add(api_case("api-load-config-nested-mapping", "config-types",
             "import jointattention as ja\nd = {}\nc = d\nfor _ in range(5000):\n"
             "    c['a'] = {}\n    c = c['a']\nja.load_config(d)", names="nested"))
add(Case("run-folder-versions-nested", "corrupt-files",
         run_case(lambda tmp: (tmp / "run/versions.json").write_text(
             '{"a": ' + "[" * DEEP + "]" * DEEP + "}")), names="versions.json"))

CELL = "run/cells/n1__seed000.npz"


def _replace_cell(content: bytes | None) -> Callable[[Path], None]:
    def edit(tmp: Path) -> None:
        path = tmp / CELL
        path.unlink()
        if content is None:
            path.mkdir()
        else:
            path.write_bytes(content)
    return edit


def _truncate(rel: str, fraction: float = 0.5) -> Callable[[Path], None]:
    def edit(tmp: Path) -> None:
        data = (tmp / rel).read_bytes()
        (tmp / rel).write_bytes(data[: int(len(data) * fraction)])
    return edit


def _write(rel: str, content: bytes | str) -> Callable[[Path], None]:
    def edit(tmp: Path) -> None:
        path = tmp / rel
        if path.is_dir():
            shutil.rmtree(path)
        if isinstance(content, bytes):
            path.write_bytes(content)
        else:
            path.write_text(content, encoding="utf-8")
    return edit


for _tag, _edit in {
    "truncated": _truncate(CELL),
    "empty": _replace_cell(b""),
    "directory": _replace_cell(None),
    "other-keys": _replace_cell(npz_bytes({"x": np.arange(3)})),
    "random-bytes": _replace_cell(random_bytes()),
    "npy-renamed": _replace_cell(npy_bytes(np.arange(10))),
}.items():
    add(Case(f"reproduce-resume-cell-{_tag}", "corrupt-files", run_case(_edit), "ok",
             check=cell_recomputed))
for _tag, _content in {"garbage": "{not json", "empty": "", "not-utf8": b"\xff\xfe{}",
                       "a-list": "[1, 2]", "missing-count": '{"7": 0.5}\n'}.items():
    add(Case(f"reproduce-resume-ceilings-{_tag}", "corrupt-files",
             run_case(_write("run/ceilings.json", _content)), "ok",
             check=ceilings_recomputed))
add(Case("reproduce-resume-timing-garbage", "corrupt-files",
         run_case(_write("run/timing.json", "{{{")), "ok", check=run_finished))
add(Case("reproduce-resume-timing-not-utf8", "corrupt-files",
         run_case(_write("run/timing.json", b"\xff\xff")), "ok", check=run_finished))
for _file, _content, _tag in (("config.toml", "[[[not toml", "garbage"),
                              ("config.toml", NOT_UTF8, "not-utf8"),
                              ("versions.json", "{not json", "garbage"),
                              ("versions.json", b"\xff\xfe", "not-utf8"),
                              ("versions.json", "[]", "a-list")):
    add(Case(f"reproduce-resume-{_file.split('.')[0]}-{_tag}", "corrupt-files",
             run_case(_write(f"run/{_file}", _content)), names=_file))
# An empty config.toml is valid TOML: the defaults, another configuration than the run's.
add(Case("reproduce-resume-config-empty", "corrupt-files",
         run_case(_write("run/config.toml", b""))))
REPORT_ARGV = ["report", "run", "--out", "report.html"]
for _file, _content, _tag in (("ceilings.json", "{not json", "garbage"),
                              ("timing.json", "{not json", "garbage"),
                              ("timing.json", b"\xff\xfe", "not-utf8"),
                              ("config.toml", NOT_UTF8, "not-utf8"),
                              ("versions.json", "{not json", "garbage"),
                              ("ceilings.json", b"\xff\xfe{}", "not-utf8"),
                              ("versions.json", "[1, 2]", "a-list"),
                              ("table.csv", b"\xff\xfe\x00garbage", "not-utf8"),
                              ("claims.csv", b"\xff\xfe\x00", "not-utf8")):
    add(Case(f"report-{_file.replace('.', '-')}-{_tag}", "corrupt-files",
             run_case(_write(f"run/{_file}", _content), REPORT_ARGV), names=_file))
add(Case("report-figure-is-directory", "corrupt-files",
         run_case(lambda tmp: (tmp / "run/fig4a_success.png").unlink()
                  or (tmp / "run/fig4a_success.png").mkdir(), REPORT_ARGV),
         names="fig4a_success.png"))
add(config_case("config-file-not-utf8", "corrupt-files", "", names="c.toml",
                extra={"c.toml": NOT_UTF8}))
add(sweep_case("sweep-spec-not-utf8", "corrupt-files", "", names="s.toml",
               extra={"s.toml": NOT_UTF8}))
add(sweep_case("sweep-spec-invalid-toml", "corrupt-files", "[grid\n", names="s.toml"))
add(sweep_case("sweep-base-not-utf8", "corrupt-files", spec_toml(base="latin.toml"),
               names="latin.toml", extra={"latin.toml": NOT_UTF8}))
for _tag, _content in {"huge-ihdr-65535": huge_png(65535, 65535),
                       "huge-ihdr-30000": huge_png(30000, 30000),
                       "huge-ihdr-int31": huge_png(2**31 - 1, 1),
                       "truncated": png_bytes()[:60],
                       "text-named-png": b"not an image at all\n",
                       "empty": b"",
                       "bad-crc": png_bytes()[:20] + b"\x00\x00\x00\x00" + png_bytes()[24:]
                       }.items():
    add(Case(f"detect-png-{_tag}", "corrupt-files",
             files_case({"bad.png": _content}, ["detect", "bad.png", "--out", "out"]),
             names="bad.png"))
add(Case("detect-image-is-directory", "corrupt-files",
         files_case({"dir.png": None}, ["detect", "dir.png", "--out", "out"]), names="dir.png"))
add(Case("detect-one-good-one-truncated", "corrupt-files",
         files_case({"good.png": png_bytes(), "bad.png": png_bytes()[:70]},
                    ["detect", "good.png", "bad.png", "--out", "out"]), names="bad.png"))



def _encoded_half(ext: str) -> bytes:
    """The first half of a noisy 320 x 240 image encoded as ``ext``.

    libjpeg and libtiff (and Pillow, on the TIFF's EXIF) have their own words about it.
    """
    import cv2

    image = np.random.default_rng(0).integers(0, 256, (240, 320, 3), dtype=np.uint8)
    data = cv2.imencode(ext, image)[1].tobytes()
    return data[: len(data) // 2]


for _ext in (".jpg", ".tif"):
    add(Case(f"detect-truncated-{_ext[1:]}", "corrupt-files",
             files_case({f"bad{_ext}": lambda e=_ext: _encoded_half(e)},
                        ["detect", f"bad{_ext}", "--out", "out"]), names=f"bad{_ext}"))

# 5. Output paths ----------------------------------------------------------------------------

OUT_COMMANDS = {  # command -> (argv before --out, kind of output: dir or file)
    "reproduce": (["reproduce", "--config", "tiny.toml", "--workers", "1"], "dir"),
    "sweep": (["sweep", "s.toml", "--workers", "1"], "dir"),
    "render": (["render"], "dir"),
    "detect": (["detect", "img.png"], "dir"),
    "gaze": (["gaze", "--config", "tiny.toml", "--condition", "n1"], "dir"),
    "parity": (["parity", "--cases", "1", "--objects", "1"], "file"),
    "train": (["train", "--config", "tiny.toml", "--condition", "n1", "--quiet"], "file"),
    "bench": (["bench", "--only", "environments"], "dir"),
}
OUT_FILES = {"tiny.toml": tiny_toml(), "s.toml": spec_toml(), "img.png": png_bytes(),
             "file.txt": "a file\n"}
for _cmd, (_argv, _kind) in OUT_COMMANDS.items():
    add(Case(f"{_cmd}-out-under-a-file", "output-paths",
             files_case(OUT_FILES, [*_argv, "--out", "file.txt/sub"]), names="file.txt"))
    add(Case(f"{_cmd}-out-is-{'a-file' if _kind == 'dir' else 'a-directory'}", "output-paths",
             files_case({**OUT_FILES, "adir": None},
                        [*_argv, "--out", "file.txt" if _kind == "dir" else "adir"]),
             names="file.txt" if _kind == "dir" else "adir"))
    add(Case(f"{_cmd}-out-unwritable-directory", "output-paths",
             (lambda a: lambda tmp: (files_case({**OUT_FILES, "ro": None}, [])(tmp),
                                     os.chmod(tmp / "ro", 0o500),
                                     [*a, "--out", "ro/out"])[-1])(_argv),
             names="ro", skip=as_root))
add(Case("reproduce-out-empty-string", "output-paths",
         files_case(OUT_FILES, ["reproduce", "--config", "tiny.toml", "--workers", "1",
                                "--out", ""])))
add(Case("report-out-is-a-directory", "output-paths",
         run_case(lambda tmp: (tmp / "adir").mkdir(), ["report", "run", "--out", "adir"]),
         names="adir"))
add(Case("report-out-under-a-file", "output-paths",
         run_case(lambda tmp: (tmp / "file.txt").write_text("x"),
                  ["report", "run", "--out", "file.txt/r.html"]), names="file.txt"))
add(Case("datasets-make-out-under-a-file", "output-paths",
         files_case(OUT_FILES, ["datasets", "make", "--n", "1", "--quiet", "file.txt/x.npz"]),
         names="file.txt"))
add(Case("datasets-make-out-is-a-directory", "output-paths",
         files_case({"adir.npz": None}, ["datasets", "make", "--n", "1", "--quiet",
                                         "adir.npz"]), names="adir.npz"))
add(Case("datasets-make-out-not-npz", "output-paths",
         files_case({}, ["datasets", "make", "--n", "1", "--quiet", "x.txt"]), names="x.txt"))
add(Case("datasets-make-out-unwritable", "output-paths",
         lambda tmp: ((tmp / "ro").mkdir(), os.chmod(tmp / "ro", 0o500),
                      ["datasets", "make", "--n", "1", "--quiet", "ro/x.npz"])[-1],
         names="ro", skip=as_root))
add(api_case("api-reproduce-out-under-a-file", "output-paths",
             "import jointattention as ja\n"
             "ja.reproduce(ja.load_config('tiny.toml'), 'file.txt/sub')",
             files=OUT_FILES, names="file.txt"))
add(api_case("api-write-report-out-is-a-directory", "output-paths",
             "import jointattention as ja\nja.write_report('run', 'adir')",
             files={"run/config.toml": tiny_toml(), "adir": None}, names="adir"))

# 6. No limits on work -----------------------------------------------------------------------

for _tag, _exp in {
    "n-steps-1e12": {"n_steps": "1000000000000"},
    "n-steps-beyond-int64": {"n_steps": "99999999999999999999"},
    "n-seeds-1e9": {"n_seeds": "1000000000"},
    "n-ceiling-trials-1e12": {"n_ceiling_trials": "1000000000000"},
    "n-ceiling-trials-beyond-int64": {"n_ceiling_trials": "99999999999999999999"},
    "bin-steps-beyond-int64": {"bin_steps": "99999999999999999999"},
}.items():
    _key = next(iter(_exp))
    add(config_case(f"reproduce-{_tag}", "work-bounds", tiny_toml(experiment=_exp),
                    "reproduce", names=_key))
add(config_case("config-seed-beyond-int64", "work-bounds",
                tiny_toml(top="seed = 99999999999999999999"), names="seed"))
add(config_case("reproduce-seed-beyond-int64", "work-bounds",
                tiny_toml(top="seed = 99999999999999999999"), "reproduce", names="seed"))
add(config_case("reproduce-memory-capacity-beyond-int64", "work-bounds",
                tiny_toml(sections="[model.memory]\ncapacity = 99999999999999999999"),
                "reproduce", names="capacity"))
# On a finished run, so that a tree that takes --workers 100000 resumes with nothing to do
# instead of forking 100000 workers (a fork-started pool launches all of them at once).
for _cmd, _argv, _kind in (("reproduce", RUN_ARGV[:-2], "run"),
                           ("sweep", SWEEP_ARGV[:-2], "sweep-ds")):
    for _w in ("-1", "100000", "-100000"):
        add(Case(f"{_cmd}-workers-{_w.replace('-', 'minus-')}", "work-bounds",
                 run_case(None, [*_argv, "--workers", _w], kind=_kind),
                 names="--workers|workers"))
add(Case("bench-workers-minus-1", "work-bounds",
         files_case({}, ["bench", "--workers", "-1"]), names="workers"))
add(sweep_case("sweep-empty-spec", "work-bounds", "", names="s.toml"))
add(sweep_case("sweep-spec-only-comments", "work-bounds", "# nothing here\n", names="s.toml"))
_GRID_1E6 = "\n".join(
    f'"{k}" = [{", ".join(v for v in vals)}]' for k, vals in {
        "model.learning_rate": [f"{0.0001 * (i + 1):.4f}" for i in range(10)],
        "model.momentum": [f"{0.05 * i:.2f}" for i in range(10)],
        "model.init_scale": [f"{0.5 + 0.1 * i:.1f}" for i in range(10)],
        "model.n_hidden": [str(i + 1) for i in range(10)],
        "agent.lm_step_deg": [f"{1.0 + i:.1f}" for i in range(10)],
        "world.caregiver.pose_noise_deg": [f"{0.5 * i:.1f}" for i in range(10)],
    }.items())
add(sweep_case("sweep-grid-1e6-points", "work-bounds", spec_toml(grid=_GRID_1E6),
               names="grid|points"))
add(sweep_case("sweep-grid-duplicate-float-values", "work-bounds",
               spec_toml(grid='"model.learning_rate" = [1e-3, 0.001]'),
               names="learning_rate"))
add(sweep_case("sweep-grid-duplicate-int-values", "work-bounds",
               spec_toml(grid='"model.n_hidden" = [1, 1]'), names="n_hidden"))
add(sweep_case("sweep-grid-duplicate-point-names", "work-bounds",
               spec_toml(grid='"datasets" = ["a/b.npz", "a_b.npz"]'),
               names="datasets|point",
               extra={"a_b.npz": small_datasets_bytes, "a/b.npz": small_datasets_bytes}))
add(sweep_case("sweep-set-n-steps-1e12", "work-bounds",
               spec_toml(set_='"experiment.n_steps" = 1000000000000'), names="n_steps"))
add(Case("parity-cases-1e12", "work-bounds",
         files_case({}, ["parity", "--cases", "1000000000000", "--objects", "1"]),
         names="--cases"))
add(Case("gaze-seed-index-1e9", "work-bounds",
         files_case({"tiny.toml": tiny_toml()}, ["gaze", "--config", "tiny.toml",
                                                 "--condition", "n1", "--seed-index",
                                                 "1000000000", "--out", "out"]),
         names="seed-index|seed_index"))
add(Case("datasets-make-n-1e9", "work-bounds",
         files_case({}, ["datasets", "make", "--n", "1000000000", "--quiet", "x.npz"]),
         names="--n"))
add(api_case("api-measure-ceiling-n-trials-1e12", "work-bounds",
             "import jointattention as ja\n"
             "ja.measure_ceiling(ja.load_config('c.toml'), 1, 10**12)",
             files={"c.toml": tiny_toml()}, names="n_trials"))
add(api_case("api-reproduce-workers-minus-1", "work-bounds",
             "import jointattention as ja\n"
             "ja.reproduce(ja.load_config('c.toml'), 'out', workers=-1)",
             files={"c.toml": tiny_toml()}, names="workers"))

# 8. Resume trusts a path --------------------------------------------------------------------


def _replace_datasets(tmp: Path) -> None:
    (tmp / "ds.npz").write_bytes(small_datasets_bytes(5, offset=40))


add(Case("reproduce-resume-datasets-replaced", "resume",
         run_case(_replace_datasets, kind="run-ds"), names="ds.npz|data set|datasets"))
add(Case("reproduce-resume-datasets-deleted", "resume",
         run_case(lambda tmp: (tmp / "ds.npz").unlink(), kind="run-ds"),
         names="ds.npz|data set|datasets"))
add(Case("reproduce-resume-datasets-replaced-by-shipped", "resume",
         run_case(lambda tmp: shutil.copy(shipped_datasets_path(), tmp / "ds.npz"),
                  kind="run-ds"), names="ds.npz|data set|datasets"))
add(Case("sweep-resume-datasets-replaced", "resume",
         run_case(_replace_datasets, SWEEP_ARGV, kind="sweep-ds"),
         names="ds.npz|data set|datasets"))
add(Case("reproduce-resume-datasets-rewritten-same-content", "resume",
         run_case(lambda tmp: (tmp / "ds.npz").write_bytes((tmp / "ds.npz").read_bytes()),
                  kind="run-ds"), "ok", check=run_finished))
add(Case("reproduce-resume-other-configuration", "resume",
         run_case(_write("tiny.toml", tiny_toml(experiment={"n_steps": "400"}))),
         names="run|configuration"))
add(Case("reproduce-resume-other-version", "resume",
         run_case(_write("run/versions.json", '{"jointattention": "0.1.0"}\n')),
         names="0.1.0"))
add(Case("reproduce-resume-cells-is-a-file", "resume",
         run_case(lambda tmp: (shutil.rmtree(tmp / "run/cells"),
                               (tmp / "run/cells").write_text("x"))),
         names="cells"))

# 9. OpenGL: fast mode needs none --------------------------------------------------------------

OSMESA = {"MUJOCO_GL": "osmesa", "PYOPENGL_PLATFORM": "osmesa"}
BOGUS_GL = {"MUJOCO_GL": "bogus"}


def _gl_case(id: str, make: Callable[[Path], Invocation], expect: str, env: dict,
             check: Callable | None = None, names: str = "") -> Case:
    return Case(id, "opengl", make, expect, names, check, env, subprocess_only=True)


def _has(rel: str) -> Callable[[Path, str], bool]:
    return lambda tmp, text: (tmp / rel).exists()


for _gl, _env in (("osmesa", OSMESA), ("bogus-gl", BOGUS_GL)):
    add(_gl_case(f"{_gl}-reproduce-fast", files_case({"tiny.toml": tiny_toml()}, RUN_ARGV),
                 "ok", _env, _has("run/claims.md")))
    add(_gl_case(f"{_gl}-config", files_case({"tiny.toml": tiny_toml()},
                                             ["config", "--config", "tiny.toml"]),
                 "ok", _env, lambda tmp, text: "n_steps = 300" in text))
    add(_gl_case(f"{_gl}-datasets-check-file", files_case({"ds.npz": small_datasets_bytes},
                                                          ["datasets", "check", "ds.npz"]),
                 "ok", _env, lambda tmp, text: "5 data sets" in text))
    add(_gl_case(f"{_gl}-render", files_case({}, ["render", "--out", "out"]), "error", _env))
    add(_gl_case(f"{_gl}-datasets-make", files_case({}, ["datasets", "make", "--n", "1",
                                                         "--quiet", "x.npz"]), "error", _env))
add(_gl_case("osmesa-config-list", files_case({}, ["config", "--list"]), "ok", OSMESA,
             lambda tmp, text: "quick" in text))
add(_gl_case("osmesa-datasets-check-shipped", files_case({}, ["datasets", "check"]), "ok",
             OSMESA, lambda tmp, text: "125 data sets" in text))
add(_gl_case("osmesa-sweep-fast",
             files_case({"tiny.toml": tiny_toml(), "s.toml": spec_toml()},
                        ["sweep", "s.toml", "--out", "sw", "--workers", "1"]),
             "ok", OSMESA, _has("sw/summary.csv")))
add(_gl_case("osmesa-report", run_case(None, ["report", "run"]), "ok", OSMESA,
             _has("run/report.html")))
add(_gl_case("osmesa-detect", files_case({"img.png": png_bytes()},
                                         ["detect", "img.png", "--out", "out"]),
             "ok", OSMESA, _has("out/img_detected.png")))
add(_gl_case("osmesa-parity", files_case({}, ["parity", "--cases", "1", "--objects", "1"]),
             "error", OSMESA))
add(_gl_case("osmesa-gaze", files_case({"tiny.toml": tiny_toml()},
                                       ["gaze", "--config", "tiny.toml", "--condition", "n1",
                                        "--out", "out"]), "error", OSMESA))
add(Case("osmesa-env-reset", "opengl",
         files_case({}, "from jointattention.env import JointAttentionEnv\n"
                        "JointAttentionEnv().reset(seed=0)"),
         env=OSMESA, subprocess_only=True))

# 10. The environment's constructor and API --------------------------------------------------

ENV = "import numpy as np\nfrom jointattention.env import JointAttentionEnv\n"
GYM = "import gymnasium\nimport jointattention.env\n"
for _tag, _kwargs, _name in (
    ("n-objects-float", "n_objects=2.5", "n_objects"),
    ("n-objects-string", "n_objects='3'", "n_objects"),
    ("n-objects-zero", "n_objects=0", "n_objects"),
    ("n-objects-negative", "n_objects=-1", "n_objects"),
    ("n-objects-1e9", "n_objects=10**9", "n_objects"),
    ("n-objects-bool", "n_objects=True", "n_objects"),
    ("n-objects-nan", "n_objects=float('nan')", "n_objects"),
    ("n-poses-zero", "n_poses=0", "n_poses"),
    ("n-poses-float", "n_poses=2.5", "n_poses"),
    ("n-poses-string", "n_poses='2'", "n_poses"),
    ("max-steps-nan", "max_steps=float('nan')", "max_steps"),
    ("max-steps-inf", "max_steps=float('inf')", "max_steps"),
    ("max-steps-zero", "max_steps=0", "max_steps"),
    ("max-steps-negative", "max_steps=-5", "max_steps"),
    ("max-steps-string", "max_steps='x'", "max_steps"),
    ("max-steps-float", "max_steps=2.5", "max_steps"),
    ("max-steps-1e9", "max_steps=10**9", "max_steps"),
    ("reward-unknown", "reward='bogus'", "reward"),
    ("render-mode-unknown", "render_mode='screen'", "render_mode"),
    ("config-int", "config=42", "config"),
    ("config-missing-file", "config='missing.toml'", "missing.toml"),
    ("config-dict", "config={'seed': 1}", "config"),
    ("caregivers-unknown", "caregivers='held-out'", "caregivers"),
    ("caregivers-none", "caregivers=None", "caregivers"),
):
    # A mapping is a configuration to load_config: the environment may take it, or refuse it.
    add(api_case(f"env-{_tag}", "env-args", f"{ENV}JointAttentionEnv({_kwargs})", names=_name,
                 expect="any" if _tag == "config-dict" else "error"))
for _tag, _kwargs, _name in (
    ("gym-make-unknown-keyword", "bogus=1", "bogus"),
    ("gym-make-n-objects-zero", "n_objects=0", "n_objects"),
    ("gym-make-max-steps-nan", "max_steps=float('nan')", "max_steps"),
    ("gym-make-n-objects-string", "n_objects='five'", "n_objects"),
    ("gym-make-caregivers-unknown", "caregivers='Unseen'", "caregivers"),
):
    add(api_case(f"env-{_tag}", "env-args",
                 f"{GYM}gymnasium.make('JointAttention-v1', {_kwargs})", names=_name))
for _tag, _action in (
    ("shape-3", "np.zeros(3)"),
    ("shape-2x2", "np.zeros((2, 2))"),
    ("scalar", "0.1"),
    ("dtype-object", "np.array([0.1, None], dtype=object)"),
    ("string", "'left'"),
    ("none", "None"),
    ("nan", "np.array([np.nan, 0.0])"),
    ("inf", "np.array([np.inf, 0.0])"),
    ("minus-inf", "np.array([0.0, -np.inf])"),
    ("list-of-strings", "['a', 'b']"),
    ("complex", "np.array([1j, 0.0])"),
):
    add(api_case(f"env-step-action-{_tag}", "env-args",
                 f"{ENV}env = JointAttentionEnv()\nenv.reset(seed=0)\nenv.step({_action})",
                 names="action"))
add(api_case("env-gym-step-action-nan", "env-args",
             f"{GYM}import numpy as np\nenv = gymnasium.make('JointAttention-v1')\n"
             "env.reset(seed=0)\nenv.step(np.array([np.nan, 0.0], dtype=np.float32))",
             names="action"))
add(api_case("env-reset-options-bogus", "env-args",
             f"{ENV}JointAttentionEnv().reset(seed=0, options={{'bogus': 1}})",
             names="options|bogus", expect="any"))

for _tag, _seed in (("string", "'x'"), ("float", "2.5"), ("negative", "-1"),
                    ("list", "[1, 2]")):
    add(api_case(f"env-reset-seed-{_tag}", "env-args",
                 f"{ENV}JointAttentionEnv().reset(seed={_seed})", names="seed"))
add(api_case("env-step-action-bool", "env-args",
             f"{ENV}env = JointAttentionEnv(obs_mode='face')\nenv.reset(seed=0)\n"
             "env.step(np.array([True, False]))", names="action"))

# The native vector environment and the Stable-Baselines3 adapter: the single env's checks.
VEC = (f"{GYM}import numpy as np\nv = gymnasium.make_vec('JointAttentionFace-v2', num_envs=4, "
       "vectorization_mode='vector_entry_point')\n")


def _says_range(tmp: Path, text: str) -> bool:
    """The message says which integers a seed may be."""
    return "[0, " in text


for _tag, _seed, _name in (
    ("list-short", "[1, 2]", "seed"),  # 2 seeds for 4 sub-environments
    ("list-negative", "[0, 1, 2, -1]", "seed[3]"),
    ("negative", "-1", "seed"),
    ("float", "0.5", "seed"),
    ("2e70", "2**70", "seed"),  # beyond the engine's integers
    ("last-beyond-int64", "2**63 - 2", "seed"),  # sub-environment 3 would take 2**63 + 1
):
    add(api_case(f"env-vector-reset-seed-{_tag}", "env-args", f"{VEC}v.reset(seed={_seed})",
                 names=_name, check=None if _tag.startswith("list") else _says_range))
# render_mode="human" without pygame: the extra to install, in one line (a fresh process:
# the case hides pygame from the importer).
add(api_case("env-render-mode-human-without-pygame", "env-args",
             f"import sys\nsys.modules['pygame'] = None\n{ENV}"
             "JointAttentionEnv(obs_mode='face', render_mode='human')",
             names="render_mode", check=lambda tmp, text: "jointattention[human]" in text,
             subprocess_only=True))
add(api_case("env-vector-caregivers-unknown", "env-args",
             VEC.replace("vectorization_mode='vector_entry_point'",
                         "vectorization_mode='vector_entry_point', caregivers='test'"),
             names="caregivers"))
add(api_case("env-vector-step-actions-bool", "env-args",
             f"{VEC}v.reset(seed=0)\nv.step(np.ones((4, 2), bool))", names="actions"))
# A copy made mid-episode steps as the original does, episodes restarting on both.
_CONTINUES = ("v.reset(seed=3)\nrng = np.random.default_rng(0)\n"
              "for _ in range(25):\n    v.step(rng.uniform(-1, 1, (4, 2)))\n"
              "w = {copy}\n"
              "for _ in range(100):\n    a = rng.uniform(-1, 1, (4, 2))\n"
              "    x, y = v.step(a), w.step(a)\n"
              "    assert all(np.array_equal(x[0][k], y[0][k]) for k in x[0])\n"
              "    assert all(np.array_equal(x[i], y[i]) for i in (1, 2, 3))\n")
for _tag, _copy in (("pickle", "pickle.loads(pickle.dumps(v))"), ("deepcopy", "copy.deepcopy(v)")):
    add(api_case(f"env-vector-{_tag}-mid-episode-continues", "env-args",
                 f"{VEC}import copy, pickle\n" + _CONTINUES.format(copy=_copy), expect="ok"))


def no_sb3() -> str | None:
    """A skip reason where Stable-Baselines3 (the rl extra) is not installed."""
    import importlib.util

    if importlib.util.find_spec("stable_baselines3") is None:
        return "needs Stable-Baselines3 (the rl extra: make test-rl)"
    return None


SB3 = ("import numpy as np\nfrom jointattention.env.sb3 import NativeVecEnv\n"
       "E = 'JointAttentionFace-N1-v2'\n")
for _tag, _source, _name in (
    ("seed-negative", "NativeVecEnv(E, num_envs=2, seed=-1)", "seed"),
    ("seed-float", "NativeVecEnv(E, num_envs=2, seed=0.5)", "seed"),
    ("seed-2e70", "NativeVecEnv(E, num_envs=2, seed=2**70)", "seed"),
    ("autoreset-mode", "NativeVecEnv(E, num_envs=2, autoreset_mode='NextStep')",
     "autoreset_mode"),
    ("vectorization-mode", "NativeVecEnv(E, num_envs=2, vectorization_mode='sync')",
     "vectorization_mode"),
    ("seed-method-negative", "NativeVecEnv(E, num_envs=2).seed(-1)", "seed"),
    ("caregivers-unknown", "NativeVecEnv(E, num_envs=2, caregivers='held-out')", "caregivers"),
    ("step-actions-bool", "v = NativeVecEnv(E, num_envs=2, seed=0)\nv.reset()\n"
                          "v.step(np.ones((2, 2), bool))", "actions"),
):
    add(api_case(f"sb3-native-{_tag}", "env-args", SB3 + _source, names=_name, skip=no_sb3))

# 11. Messages -------------------------------------------------------------------------------

for _tag, _section, _name in (
    ("fov-deg-500", "[world.camera]\nfov_deg = 500", "world.camera.fov_deg"),
    ("n-objects-zero", "[[experiment.conditions]]\nn_objects = 0",
     "experiment.conditions[0].n_objects"),
    ("max-steps-zero", "[agent]\nmax_steps = 0", "agent.max_steps"),
    ("gate-width-negative", "[model.gate]\nwidth_steps = -1.0", "model.gate.width_steps"),
    ("memory-capacity-zero", "[model.memory]\ncapacity = 0", "model.memory.capacity"),
    ("n-hidden-zero", "[model]\nn_hidden = 0", "model.n_hidden"),
    ("face-window-width-2", "[world.face_window]\nwidth_px = 2", "world.face_window.width_px"),
    ("unknown-nested-key", "[world.camera]\nbogus = 1", "world.camera.bogus"),
    ("pan-limits-out-of-range", "[world.head]\npan_limits_deg = [-300.0, 60.0]",
     "world.head.pan_limits_deg"),
):
    add(config_case(f"message-{_tag}", "messages", tiny_toml(sections=_section),
                    names=_name, check=no_none))
for _tag, _text, _name in (
    ("min-area-zero", tiny_toml(sections="[detector]\nmin_area_px = 0"),
     "detector.min_area_px"),
    ("n-steps-zero", tiny_toml(experiment={"n_steps": "0"}), "experiment.n_steps"),
    ("bin-steps-zero", tiny_toml(experiment={"bin_steps": "0"}), "experiment.bin_steps"),
    ("seed-negative", tiny_toml(top="seed = -1"), "seed"),
    ("gate-midpoint-negative", tiny_toml(sections="[model.gate]\nmidpoint_steps = -5.0"),
     "model.gate.midpoint_steps"),
):
    add(config_case(f"message-open-range-{_tag}", "messages", _text, names=_name,
                    check=no_none))
add(config_case("message-condition-n-objects-zero", "messages",
                tiny_toml(conditions=condition("n1", 0)),
                names="experiment.conditions[0].n_objects", check=no_none))
add(config_case("message-condition-gate-rate-2", "messages",
                tiny_toml(conditions=condition(
                    "n1", 1, 'model = { gate = { kind = "constant", rate = 2.0 } }')),
                names="experiment.conditions[0].model.gate.rate", check=no_none))
add(sweep_case("message-sweep-set-fov-deg-500", "messages",
               spec_toml(set_='"world.camera.fov_deg" = 500'), names="world.camera.fov_deg",
               check=no_none))
add(sweep_case("message-sweep-grid-gate-width-negative", "messages",
               spec_toml(grid='"model.gate.width_steps" = [-1.0]'),
               names="model.gate.width_steps", check=no_none))
add(Case("message-random-bytes-not-pickled-reproduce", "messages",
         files_case({"c.toml": tiny_toml(top='datasets = "rand.npz"'),
                     "rand.npz": random_bytes(seed=7)}, _config_argv("reproduce")),
         names="rand.npz", check=not_pickled))
add(Case("message-random-bytes-not-pickled-api", "messages",
         files_case({"rand.npz": random_bytes(seed=8)},
                    "import jointattention as ja\nja.load_datasets('rand.npz')"),
         names="rand.npz", check=not_pickled))

# CLI argument faults ------------------------------------------------------------------------

for _tag, _argv, _name in (
    ("reproduce-unknown-preset", ["reproduce", "--preset", "nosuch", "--out", "out"], "nosuch"),
    ("reproduce-config-unknown-preset", ["reproduce", "--config", "nosuch", "--out", "out"],
     "nosuch"),
    ("config-unknown-preset", ["config", "--config", "nosuch"], "nosuch"),
    ("gaze-unknown-preset", ["gaze", "--preset", "nosuch", "--out", "out"], "nosuch"),
    ("bench-run-unknown-preset", ["bench", "--run", "nosuch"], "nosuch"),
    ("bench-only-unknown-section", ["bench", "--only", "nosuch"], "nosuch"),
    ("render-unknown-preset", ["render", "--config", "nosuch", "--out", "out"], "nosuch"),
    ("parity-unknown-preset", ["parity", "--config", "nosuch", "--cases", "1"], "nosuch"),
    ("config-missing-file", ["config", "--config", "missing.toml"], "missing.toml"),
    ("reproduce-missing-config-file", ["reproduce", "--config", "missing.toml", "--out", "out"],
     "missing.toml"),
    ("sweep-missing-spec", ["sweep", "missing.toml", "--out", "out"], "missing.toml"),
    ("report-missing-folder", ["report", "missing"], "missing"),
    ("datasets-check-missing-file", ["datasets", "check", "missing.npz"], "missing.npz"),
    ("detect-missing-image", ["detect", "missing.png", "--out", "out"], "missing.png"),
    ("gaze-unknown-condition", ["gaze", "--config", "tiny.toml", "--condition", "nosuch",
                                "--out", "out"], "nosuch"),
    ("gaze-condition-parent-path", ["gaze", "--config", "tiny.toml", "--condition", "../x",
                                    "--out", "out"], "../x"),
    ("config-directory-as-config", ["config", "--config", "adir.toml"], "adir.toml"),
    ("sweep-directory-as-spec", ["sweep", "adir.toml", "--out", "out"], "adir.toml"),
    ("datasets-check-directory", ["datasets", "check", "adir.toml"], "adir.toml"),
    ("report-file-as-folder", ["report", "file.txt"], "file.txt"),
    ("config-empty-config", ["config", "--config", ""], ""),
    ("reproduce-empty-config", ["reproduce", "--config", "", "--out", "out", "--workers", "1"],
     ""),
    ("sweep-empty-spec-path", ["sweep", "", "--out", "out"], ""),
    ("report-empty-path", ["report", ""], ""),
    ("datasets-check-empty-path", ["datasets", "check", ""], ""),
    ("datasets-make-empty-out", ["datasets", "make", "--n", "1", "--quiet", ""], ""),
    ("detect-empty-image-path", ["detect", "", "--out", "out"], ""),
    ("parity-cases-zero", ["parity", "--cases", "0", "--objects", "1"], "--cases"),
    ("parity-cases-negative", ["parity", "--cases", "-1", "--objects", "1"], "--cases"),
    ("parity-objects-zero", ["parity", "--cases", "1", "--objects", "0"], "--objects"),
    ("parity-objects-21", ["parity", "--cases", "1", "--objects", "21"], "--objects"),
    ("parity-objects-negative", ["parity", "--cases", "1", "--objects", "-3"], "--objects"),
    ("parity-seed-negative", ["parity", "--cases", "1", "--objects", "1", "--seed", "-1"],
     "--seed"),
    ("gaze-seed-index-negative", ["gaze", "--config", "tiny.toml", "--condition", "n1",
                                  "--seed-index", "-1", "--out", "out"], "seed"),
    ("datasets-make-n-zero", ["datasets", "make", "--n", "0", "--quiet", "x.npz"], "--n"),
    ("datasets-make-n-negative", ["datasets", "make", "--n", "-5", "--quiet", "x.npz"], "--n"),
    ("datasets-make-seed-negative", ["datasets", "make", "--n", "1", "--seed", "-1",
                                     "--quiet", "x.npz"], "--seed"),
    ("render-seed-negative", ["render", "--seed", "-1", "--out", "out"], "--seed"),
    ("render-seed-beyond-int64", ["render", "--seed", "99999999999999999999", "--out", "out"],
     "--seed"),
    ("reproduce-workers-not-int", ["reproduce", "--workers", "two", "--out", "out"],
     "--workers"),
    ("reproduce-address-without-ray", ["reproduce", "--config", "tiny.toml", "--out", "out",
                                       "--address", "1.2.3.4:6379"], "--address"),
    ("sweep-address-without-ray", ["sweep", "s.toml", "--out", "out", "--address", "x:1"],
     "--address"),
    ("reproduce-backend-unknown", ["reproduce", "--backend", "slurm", "--out", "out"],
     "--backend"),
    ("detect-face-unknown", ["detect", "img.png", "--face", "dlib", "--out", "out"], "--face"),
):
    add(Case(f"cli-{_tag}", "cli-args",
             files_case({**OUT_FILES, "adir.toml": None}, _argv), names=_name))

# Configuration types ------------------------------------------------------------------------

for _tag, _text, _name in (
    ("n-steps-string", tiny_toml(experiment={"n_steps": '"300"'}), "n_steps"),
    ("n-steps-float", tiny_toml(experiment={"n_steps": "300.5"}), "n_steps"),
    ("n-seeds-bool", tiny_toml(experiment={"n_seeds": "true"}), "n_seeds"),
    ("world-not-a-table", tiny_toml(top="world = 5"), "world"),
    ("conditions-string", tiny_toml(experiment={"conditions": '"n1"'}, conditions=""),
     "conditions"),
    ("conditions-numbers", tiny_toml(experiment={"conditions": "[1, 2]"}, conditions=""),
     "conditions"),
    ("condition-model-number", tiny_toml(conditions=condition("n1", 1, "model = 5")),
     "model"),
    ("model-kind-unknown", tiny_toml(sections='[model]\nkind = "nosuch"'), "kind"),
    ("gate-kind-number", tiny_toml(sections="[model.gate]\nkind = 3"), "kind"),
    ("datasets-number", tiny_toml(top="datasets = 5"), "datasets"),
    ("offset-two-numbers", tiny_toml(sections="[world.camera]\noffset_m = [1.0, 2.0]"),
     "offset_m"),
    ("perception-unknown", tiny_toml(experiment={"perception": '"bogus"'}), "perception"),
    ("top-level-unknown-key", tiny_toml(top="bogus = 1"), "bogus"),
    ("gate-rate-string", tiny_toml(conditions=condition(
        "n1", 1, 'model = { gate = { kind = "constant", rate = "x" } }')), "rate"),
    ("condition-n-objects-float", tiny_toml(conditions=condition("n1", "1.5")), "n_objects"),
    ("condition-unknown-key", tiny_toml(conditions=condition("n1", 1, "bogus = 1")), "bogus"),
    ("interest-weights-strings", tiny_toml(sections='[agent]\ninterest_weights = ["a", "b", '
                                                    '"c"]'), "interest_weights"),
    ("n-objects-beyond-int64", tiny_toml(conditions=condition("n1", "99999999999999999999")),
     "n_objects"),
):
    add(config_case(f"config-type-{_tag}", "config-types", _text, names=_name))
for _tag, _spec, _name in (
    ("grid-not-a-list", spec_toml(grid='"model.n_hidden" = 7'), "n_hidden"),
    ("grid-empty-list", spec_toml(grid='"model.n_hidden" = []'), "n_hidden"),
    ("grid-unknown-setting", spec_toml(grid='"model.bogus" = [1]'), "bogus"),
    ("grid-no-section", spec_toml(grid='"nosection.x" = [1]'), "nosection"),
    ("unknown-top-key", spec_toml(top="bogus = 1"), "bogus"),
    ("base-unknown-preset", spec_toml(base="nosuch"), "nosuch"),
    ("base-missing-file", spec_toml(base="missing.toml"), "missing.toml"),
    ("set-not-a-table", 'base = "tiny.toml"\nset = 5\n', "set"),
    ("grid-not-a-table", 'base = "tiny.toml"\ngrid = [1, 2]\n', "grid"),
    ("base-number", "base = 5\n", "base"),
    ("grid-value-table", spec_toml(grid='"model.n_hidden" = [{ a = 1 }]'), "n_hidden"),
):
    add(sweep_case(f"sweep-type-{_tag}", "config-types", _spec, names=_name))
for _tag, _src, _name in (
    ("load-config-int", "import jointattention as ja\nja.load_config(42)", "42"),
    ("load-config-empty", "import jointattention as ja\nja.load_config('')", ""),
    ("condition-n-objects-float",
     "import jointattention as ja\nja.ConditionConfig(n_objects=2.5)", "n_objects"),
    ("condition-model-list", "import jointattention as ja\nja.ConditionConfig(model=[1])",
     "model"),
    ("run-cell-seed-index-negative",
     "import jointattention as ja\nc = ja.load_config('c.toml')\n"
     "ja.run_cell(c, c.experiment.conditions[0], -1)", "seed_index"),
    ("measure-ceiling-n-objects-zero",
     "import jointattention as ja\nja.measure_ceiling(ja.load_config('c.toml'), 0)",
     "n_objects"),
    ("load-datasets-missing", "import jointattention as ja\nja.load_datasets('missing.npz')",
     "missing.npz"),
    ("write-report-missing", "import jointattention as ja\nja.write_report('missing')",
     "missing"),
):
    add(api_case(f"api-{_tag}", "config-types", _src, names=_name,
                 files={"c.toml": tiny_toml()}))

# The Python API's other arguments: one named error, never a bare TypeError or a division by 0.
_API = "import jointattention as ja\nc = ja.load_config('c.toml')\n"
_IMPORT = "ja.import_recording('rec', face='template', "
for _tag, _src, _name in (
    ("reproduce-workers-string", "ja.reproduce(c, 'out', workers='2')", "workers"),
    ("reproduce-workers-float", "ja.reproduce(c, 'out', workers=2.5)", "workers"),
    ("reproduce-workers-bool", "ja.reproduce(c, 'out', workers=True)", "workers"),
    ("run-experiment-workers-string", "ja.run_experiment(c, 'out', workers='2')", "workers"),
    ("import-recording-face-size-zero", _IMPORT + "face_size_px=0)", "face_size_px"),
    ("import-recording-face-size-string", _IMPORT + "face_size_px='x')", "face_size_px"),
    ("import-recording-face-height-zero", _IMPORT + "face_size_px=(30, 0))", "face_size_px"),
    ("import-recording-face-width-zero", _IMPORT + "face_size_px=(0, 25))", "face_size_px"),
    ("import-recording-face-unknown", "ja.import_recording('rec', face='x')", "face"),
    ("import-recording-min-score-string", _IMPORT + "min_score='x')", "min_score"),
    ("import-recording-template-string", _IMPORT + "template='x')", "template"),
    ("load-model-robot-string",
     f"ja.load_model({str(REPO / 'docs/results/robot/paper_n5_seed0.npz')!r}, robot='x')", "robot"),
    ("save-model-agent-string", "ja.save_model('x', 'm.npz', config=c, condition='n1')",
     "agent"),
    ("run-cell-condition-string", "ja.run_cell(c, 'x', 0)", "condition"),
):
    add(api_case(f"api-{_tag}", "config-types", _API + _src, names=_name,
                 files={"c.toml": tiny_toml(), **RECORDING}))


# Issue 61: the output place first, the shipped files, memory in range, contradictions, quiet
# refusals -----------------------------------------------------------------------------------

# a model of 30x25 faces
SHIPPED_MODEL = REPO / "docs" / "results" / "generalise" / "population_n10.npz"


def _model_files(tmp: Path) -> None:
    """The shipped model as m.npz, the shipped data sets as ds.npz and a PNG, in ``tmp``."""
    shutil.copy(SHIPPED_MODEL, tmp / "m.npz")
    shutil.copy(shipped_datasets_path(), tmp / "ds.npz")
    write_files(tmp, {"img.png": png_bytes(), "tiny.toml": tiny_toml()})


def model_case(argv: list[str] | str, edit: Callable[[Path], None] | None = None
               ) -> Callable[[Path], Invocation]:
    """A ``make`` that writes :func:`_model_files`, changes them with ``edit``, returns argv."""
    def make(tmp: Path) -> Invocation:
        _model_files(tmp)
        if edit is not None:
            edit(tmp)
        return list(argv) if isinstance(argv, list) else argv
    return make


EVALUATE = ["evaluate", "m.npz", "--datasets", "ds.npz", "--trials", "1", "--objects", "1"]
PROC_OUT = {  # command -> (argv before --out, the output under /proc)
    "closed-loop": (["closed-loop", "m.npz", "--datasets", "ds.npz", "--objects", "1",
                     "--trials", "1"], "/proc/jointattention.md"),
    "follow": (["follow", "m.npz", "img.png"], "/proc/jointattention"),
    "train": (["train", "--config", "tiny.toml", "--condition", "n1", "--quiet"],
              "/proc/jointattention.npz"),
    "detect": (["detect", "img.png"], "/proc/jointattention"),
    "reproduce": (["reproduce", "--config", "tiny.toml", "--workers", "1"],
                  "/proc/jointattention"),
    "parity": (["parity", "--cases", "1", "--objects", "1"], "/proc/jointattention.md"),
    "render": (["render"], "/proc/jointattention"),
    "evaluate": (EVALUATE, "/proc/jointattention"),
    "faces": (["faces", "--n", "1", "--caregivers", "1"], "/proc/jointattention.md"),
    "gaze": (["gaze", "--config", "tiny.toml", "--condition", "n1"], "/proc/jointattention"),
    "datasets-import": (["datasets", "import", "rec"], "/proc/jointattention.npz"),
}
for _cmd, (_argv, _out) in PROC_OUT.items():
    add(Case(f"{_cmd}-out-under-proc", "output-paths", model_case([*_argv, "--out", _out]),
             names="/proc"))
add(Case("datasets-make-out-under-proc", "output-paths",
         files_case({}, ["datasets", "make", "--n", "1", "--quiet", "/proc/jointattention.npz"]),
         names="/proc"))
add(Case("report-out-under-proc", "output-paths",
         run_case(None, ["report", "run", "--out", "/proc/jointattention.html"]), names="/proc"))


def _fifo(rel: str, link: str | None = None) -> Callable[[Path], None]:
    """An edit: a FIFO at ``rel`` (and a symbolic link ``link`` to it)."""
    def edit(tmp: Path) -> None:
        os.mkfifo(tmp / rel)
        if link is not None:
            os.symlink(rel, tmp / link)
    return edit


# As root, `faces --out /dev/full` replaced the device: a FIFO stands for it (rename over it)
add(Case("faces-out-is-a-fifo", "output-paths",
         model_case(["faces", "--n", "1", "--caregivers", "1", "--out", "f.md"], _fifo("f.md")),
         names="f.md"))
add(Case("parity-out-is-a-link-to-a-fifo", "output-paths",
         model_case(["parity", "--cases", "1", "--objects", "1", "--out", "link.md"],
                    _fifo("f.md", "link.md")), names="link.md"))
add(Case("closed-loop-out-is-a-fifo", "output-paths",
         model_case(["closed-loop", "m.npz", "--datasets", "ds.npz", "--objects", "1",
                     "--trials", "1", "--out", "f.md"], _fifo("f.md")), names="f.md"))
add(Case("datasets-make-out-is-a-fifo", "output-paths",
         model_case(["datasets", "make", "--n", "1", "--quiet", "f.npz"], _fifo("f.npz")),
         names="f.npz"))
for _cmd, _argv in (("evaluate", EVALUATE), ("closed-loop", PROC_OUT["closed-loop"][0]),
                    ("follow", PROC_OUT["follow"][0]),
                    ("faces", PROC_OUT["faces"][0])):
    add(Case(f"{_cmd}-out-empty-string", "output-paths", model_case([*_argv, "--out", ""]),
             names="--out"))

_HELD: list = []  # processes holding an output lock while a case runs (ended at exit)
atexit.register(lambda: [held.kill() for held in _HELD])

_HOLD = """import sys, time
try:
    from jointattention._files import output_lock
except ImportError:
    print("none", flush=True); sys.exit()
with output_lock(sys.argv[1]):
    print("held", flush=True)
    time.sleep(3600)
"""


def _hold_output(rel: str) -> Callable[[Path], None]:
    """An edit: hold the output lock of ``rel``, as another command writing it would.

    Held by a process of the tree under test (this one imports nothing of it); a tree without
    output locks has nothing to hold: there the case runs unlocked.
    """
    def edit(tmp: Path) -> None:
        held = subprocess.Popen([sys.executable, "-c", _HOLD, str(tmp / rel)],
                                stdout=subprocess.PIPE, text=True,
                                env={**os.environ, "PYTHONPATH": str(SRC)})
        _HELD.append(held)
        held.stdout.readline()  # "held" once the lock is taken ("none": no locks there)
    return edit


add(Case("evaluate-out-written-by-another", "output-paths",
         model_case([*EVALUATE, "--out", "out"], _hold_output("out")),
         names="another command"))
add(Case("parity-out-written-by-another", "output-paths",
         model_case(["parity", "--cases", "1", "--objects", "1", "--out", "t.md"],
                    _hold_output("t.md")), names="another command"))


def _damaged_install(name: str, content: bytes | None) -> Callable[[Path], None]:
    """An edit: a copy of the package under test in ``pkg`` with data file ``name`` damaged.

    ``content``: the file's new bytes; None: removed. The case's PYTHONPATH is ``pkg``.
    """
    def edit(tmp: Path) -> None:
        shutil.copytree(SRC / "jointattention", tmp / "pkg" / "jointattention",
                        ignore=shutil.ignore_patterns("__pycache__"))
        target = tmp / "pkg" / "jointattention" / "data" / name
        if content is None:
            target.unlink()
        else:
            target.write_bytes(content)
    return edit


def _shipped_bytes(name: str) -> bytes:
    return (SRC / "jointattention" / "data" / name).read_bytes()


INSTALL_ENV = {"PYTHONPATH": "pkg", "PYTHONDONTWRITEBYTECODE": "1"}
for _name, _tag, _content in (
    ("face_detection_short_range.tflite", "truncated",
     lambda: _shipped_bytes("face_detection_short_range.tflite")[:4096]),
    ("face_detection_short_range.tflite", "missing", lambda: None),
    ("blazeface_calibration.npz", "random-bytes", random_bytes),
    ("blazeface_calibration.npz", "missing", lambda: None),
    ("blazeface_calibration.npz", "no-weights",
     lambda: npz_bytes({"stages": np.zeros((1, 2)), "meta": np.array("{}")})),
):
    add(Case(f"follow-installed-{_name.split('.')[0].replace('_', '-')}-{_tag}",
             "corrupt-files",
             (lambda n, c: model_case(["follow", "m.npz", "img.png"],
                                      lambda tmp: _damaged_install(n, c())(tmp)))(
                 _name, _content),
             names=f"{_name}|reinstall", env=INSTALL_ENV, subprocess_only=True,
             check=lambda tmp, text: "reinstall" in text))
add(Case("datasets-check-installed-caregiver-125-truncated", "corrupt-files",
         lambda tmp: (_damaged_install("caregiver_125.npz",
                                       _shipped_bytes("caregiver_125.npz")[:1000])(tmp),
                      ["datasets", "check"])[-1],
         names="caregiver_125.npz", env=INSTALL_ENV, subprocess_only=True,
         check=lambda tmp, text: "reinstall" in text))

# In range, beyond the machine: 539 GiB of replay memory (1.1 kB features, 10 million trials)
HUGE_REPLAY = ('[model]\nlearner = "population"\n\n[model.population]\n'
               "replay_capacity = 10000000\ncell_px = 2\nn_orientations = 36")
add(Case("train-population-replay-capacity-in-range-beyond-memory", "work-bounds",
         files_case({"c.toml": tiny_toml(sections=HUGE_REPLAY)},
                    ["train", "--config", "c.toml", "--condition", "n1", "--quiet", "--out",
                     "m.npz"]), names="replay_capacity"))
add(config_case("reproduce-population-replay-capacity-in-range-beyond-memory", "work-bounds",
                tiny_toml(sections=HUGE_REPLAY), "reproduce", names="replay_capacity"))


def _frozen_huge_replay(tmp: Path) -> None:
    """m.npz: the shipped model, its configuration naming a 10-million-trial replay memory."""
    with np.load(tmp / "m.npz") as z:
        arrays = {k: z[k] for k in z.files}
    meta = json.loads(str(arrays["meta"]))
    meta["config"] = re.sub(r"replay_capacity = \d+", "replay_capacity = 10000000",
                            meta["config"])
    arrays["meta"] = np.array(json.dumps(meta))
    (tmp / "m.npz").write_bytes(npz_bytes(arrays))


# A fresh process: its trials may compile the kernels first (tens of seconds, once a machine)
add(Case("evaluate-frozen-model-of-a-huge-replay-memory", "work-bounds",
         model_case(EVALUATE, _frozen_huge_replay), expect="ok",
         check=lambda tmp, text: "of the ceiling" in text, subprocess_only=True))
add(Case("follow-frozen-model-of-a-huge-replay-memory", "work-bounds",
         model_case(["follow", "m.npz", "img.png"], _frozen_huge_replay), expect="ok",
         check=lambda tmp, text: '"command_deg"' in text))

# Contradictory options: one line naming both
for _face in ("haar", "template"):
    add(Case(f"follow-landmarks-only-with-face-{_face}", "cli-args",
             model_case(["follow", "m.npz", "img.png", "--face", _face, "--landmarks-only"]),
             names="--landmarks-only", check=lambda tmp, text: "--face" in text))
add(Case("evaluate-poses-without-caregivers", "cli-args",
         model_case([*EVALUATE, "--poses", "10"]), names="--poses",
         check=lambda tmp, text: "--caregivers" in text))
add(Case("datasets-make-overwrites-its-caregivers-of", "cli-args",
         model_case(["datasets", "make", "--n", "2", "--seed", "7", "--quiet",
                     "--caregivers-of", "ds.npz", "./ds.npz"]), names="--caregivers-of"))


# No output before the verdict
def _windows_20x20(tmp: Path) -> None:
    """w20.npz: five data sets whose face windows are 20x20 (a robot's recording: no seed)."""
    arrays = small_arrays(5)
    arrays["face"] = arrays["face"][:, :20, :20].copy()
    arrays["meta"] = np.array(json.dumps({"generator": "a robot"}))
    (tmp / "w20.npz").write_bytes(npz_bytes(arrays))


add(Case("closed-loop-windows-20x20-refused-before-any-bar", "messages",
         model_case(["closed-loop", "m.npz", "--datasets", "w20.npz", "--objects", "1",
                     "--trials", "1"], _windows_20x20), names="20x20"))
add(Case("datasets-import-missing-folder-refused-before-any-bar", "messages",
         files_case({}, ["datasets", "import", "missing", "--out", "x.npz"]),
         names="missing"))
add(api_case("gym-make-v2-bad-argument-without-out-of-date-warning", "messages",
             "import warnings\n"
             "with warnings.catch_warnings(record=True) as caught:\n"
             "    import gymnasium as gym\n"
             "    import jointattention.env\n"
             "    try:\n"
             "        gym.make('JointAttention-v2', n_objects=2.5)\n"
             "    finally:\n"
             "        noise = [str(w.message) for w in caught if 'out of date' in str(w.message)]\n"
             "        if noise:\n"
             "            raise RuntimeError('warned before the error: ' + noise[0])\n",
             names="n_objects", subprocess_only=True))


def _check_unique() -> None:
    seen: set[str] = set()
    for case in CASES:
        if case.id in seen:
            raise ValueError(f"duplicate case id {case.id!r}")
        if case.fault not in FAULTS:
            raise ValueError(f"{case.id}: unknown fault {case.fault!r}")
        seen.add(case.id)


_check_unique()
