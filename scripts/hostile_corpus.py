"""Run the hostile-input corpus (tests/hostile/cases.py), each case in its own subprocess.

Usage::

    python scripts/hostile_corpus.py [--src DIR] [--timeout 20] [--only SUBSTR] [--json OUT]
                                     [--markdown OUT.md]

Each case runs as ``python -m jointattention ...`` (or ``python -c ...`` for API cases) with
``PYTHONPATH=DIR`` (default: this repository's ``src``) and ``MUJOCO_GL=egl`` unless the case
sets its own environment, in a fresh temporary directory as its working directory, one at a
time, killed after ``--timeout`` seconds. It prints one line per case, then how many cases
ended in each outcome, overall and per fault class (see the outcomes in
``tests/hostile/cases.py``); with ``--json`` it writes every case's outcome to a file, and
with ``--markdown`` the table it prints (the manual includes docs/results/bad-input/corpus.md).

This process imports nothing of ``jointattention``, so it can measure any source tree.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from collections import Counter
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests"))

from hostile import cases  # noqa: E402


def _table(results: list[dict]) -> str:
    """Outcome -> count overall, then a fault x outcome matrix, as Markdown."""
    overall = Counter(r["outcome"] for r in results)
    outcomes = [o for o in cases.OUTCOMES if overall[o]]
    lines = ["| outcome | cases |", "|---|---:|"]
    lines += [f"| {o} | {overall[o]} |" for o in outcomes]
    lines.append(f"| total | {len(results)} |")
    lines += ["", "| fault | " + " | ".join(outcomes) + " | total |",
              "|---|" + "---:|" * (len(outcomes) + 1)]
    for fault in cases.FAULTS:
        mine = Counter(r["outcome"] for r in results if r["fault"] == fault)
        if mine:
            cells = " | ".join(str(mine[o]) if mine[o] else "" for o in outcomes)
            lines.append(f"| {fault} | {cells} | {sum(mine.values())} |")
    handled = sum(r["outcome"] in r["good"] for r in results)
    lines += ["", f"handled as expected (clean refusal, or success where expected): "
                  f"{handled} of {len(results)}"]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    """Run the selected cases and print the table; returns the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--src", type=Path, default=REPO / "src",
                        help="the source tree to measure (default: this repository's src)")
    parser.add_argument("--timeout", type=float, default=20.0,
                        help="seconds before a case counts as no-bound (default: 20)")
    parser.add_argument("--only", metavar="SUBSTR",
                        help="only the cases whose id contains SUBSTR (or whose fault is it)")
    parser.add_argument("--json", type=Path, metavar="OUT",
                        help="also write every case's outcome to this JSON file")
    parser.add_argument("--markdown", type=Path, metavar="OUT.md",
                        help="also write the table, with the command and its time, to this file")
    args = parser.parse_args(argv)
    src = args.src.resolve()
    if not (src / "jointattention" / "__init__.py").is_file():
        parser.error(f"--src {src}: no jointattention package there")
    cases.SRC = src
    selected = [c for c in cases.CASES
                if not args.only or args.only in c.id or args.only == c.fault]
    if not selected:
        parser.error(f"--only {args.only!r}: no case matches")
    print(f"{len(selected)} cases against {src}, timeout {args.timeout:g} s", file=sys.stderr)
    start = time.perf_counter()
    results = []
    for i, case in enumerate(selected, 1):
        result = cases.run_subprocess(case, src, args.timeout)
        result.update(expect=case.expect, good=list(case.good))
        results.append(result)
        print(f"[{i:3d}/{len(selected)}] {result['outcome']:<12} {result['seconds']:6.1f}s "
              f"{case.id}", file=sys.stderr, flush=True)
    wall_s = time.perf_counter() - start
    assert "jointattention" not in sys.modules, "the corpus must not import jointattention"
    table = _table(results)
    print(table)
    print(f"\n{len(results)} cases in {wall_s / 60:.1f} min")
    if args.markdown:
        command = "python scripts/hostile_corpus.py" + (f" --timeout {args.timeout:g}"
                                                        if args.timeout != 20.0 else "")
        args.markdown.write_text(
            f"{table}\n\n(`{command}`, {time.strftime('%d %B %Y')}: {len(results)} cases, one "
            f"at a time in their own processes, {wall_s / 60:.1f} min on this machine.)\n",
            encoding="utf-8")
    if args.json:
        by_outcome: dict[str, list[str]] = {}
        for r in results:
            by_outcome.setdefault(r["outcome"], []).append(r["id"])
        args.json.write_text(json.dumps({
            "src": str(src), "timeout_s": args.timeout, "wall_s": round(wall_s, 1),
            "counts": dict(Counter(r["outcome"] for r in results)),
            "by_fault": {f: dict(Counter(r["outcome"] for r in results if r["fault"] == f))
                         for f in cases.FAULTS},
            "by_outcome": by_outcome, "cases": results}, indent=1) + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
