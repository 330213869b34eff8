"""Recording caregiver data sets from the simulated world (the paper's protocol).

Streams: a world draws its identities and scenes from the random stream named ``"world"`` of
its seed; :data:`HELD_OUT` names a stream that no training world draws from, so recordings
made from it hold caregivers and poses that no recording of the ``"world"`` stream holds, for
every seed (``datasets make --held-out``).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from .. import rng as rngs
from .._version import __version__
from ..agent.eye_sockets import eye_patches
from ..agent.faces import face_window, window_of
from ..agent.finders import DEFAULT_FACE, finder_for
from ..datasets import CaregiverDatasets, load
from ..errors import DatasetError
from .face import BODIES as EYE_BODIES
from .identity import Caregiver, caregiver_from_dict, sample_caregiver
from .mjcf import FOVEA_SUPERSAMPLE
from .options import EyeWindowConfig, WorldConfig
from .simulator import World

__all__ = ["CUTS", "HELD_OUT", "capture_eye_window", "capture_face_window", "caregivers_of",
           "eye_box", "eye_window_at", "eye_window_kept", "face_box", "head_box", "make_datasets",
           "sockets_in_window", "split_evenly"]

HELD_OUT = "held-out"  # the stream of held-out recordings; no training world draws from it

CUTS = ("box", "finder")  # where make_datasets cuts the face windows
FACE_FINDER = DEFAULT_FACE  # the robot's face finder, as follow and the closed loop use it


def head_box(world: World) -> tuple[np.ndarray, float]:
    """The image position of the caregiver's head centre and the head's apparent height."""
    kin, state = world.kinematics, world.state
    theta = world.head_angle_rad
    centre = kin.project(state.head_pos_m, theta)[0][0]
    radius = kin.apparent_radius_px(state.head_pos_m, [state.face_radius_m], theta)[0]
    return centre, float(2 * radius)


def face_box(world: World) -> tuple[np.ndarray, float]:
    """Where the face window is cut in the robot's current view.

    The image position of the caregiver's head centre, and the crop's height (``face_window.margin``
    times the head's apparent height, :func:`head_box`).
    """
    centre, height = head_box(world)
    return centre, world.config.face_window.margin * height


def eye_box(world: World) -> tuple[np.ndarray, float]:
    """The image position of the midpoint of the caregiver's eyes, and their distance (px).

    From the eyeballs' centres (they stay where they are as the eyes turn), in camera pixels.
    """
    uv = _eyes_px(world)
    return uv.mean(axis=0), float(np.linalg.norm(uv[0] - uv[1]))


def _eyes_px(world: World) -> np.ndarray:
    """The eyeballs' centres in camera pixels (2 eyes, x y), the left eye first."""
    eyes = np.stack([world.data.body(body).xpos for body in EYE_BODIES])
    uv, _ = world.kinematics.project(eyes, world.head_angle_rad)
    return uv


def _placed(centre_px, distance_px: float, error) -> tuple[np.ndarray, float]:
    """Where a window placed with ``error`` ((dx, dy, log width) in eye distances) lies."""
    if error is None:
        return centre_px, distance_px
    return (np.asarray(centre_px) + np.asarray(error[:2]) * distance_px,
            distance_px * np.exp(error[2]))


_PLACEMENT_KEY = 0x3E7E  # the eye window's placement error: apart from the scene's noise


def capture_eye_window(world: World) -> np.ndarray:
    """The eye window of the robot's current view: grey levels (height, width) of ``eye_window``.

    A field ``span`` eye distances wide around the eyes' midpoint (:func:`eye_box`), seen
    through the fovea (:func:`eye_window_at`). With ``placement_sd`` the field is placed and
    sized with the error an eye finder would make, drawn once per scene; with
    ``socket_patch_px``, what the robot keeps of it (:func:`eye_window_kept`).
    """
    sd = world.config.eye_window.placement_sd
    window = eye_window_at(world, *eye_box(world), _placement_error(world, sd) if sd > 0 else None)
    return eye_window_kept(world.config.eye_window, window)


def eye_window_kept(eye_window: EyeWindowConfig, window: np.ndarray) -> np.ndarray:
    """What the robot keeps of an eye ``window``: its socket patches (``socket_patch_px``), or it.

    The patches are the robot's own (:func:`~jointattention.agent.eye_sockets.eye_patches`),
    around the sockets its ``socket_finder`` finds.
    """
    if not eye_window.socket_patch_px:
        return window
    return eye_patches(window, eye_window.span, eye_window.socket_patch_px,
                       eye_window.socket_finder)


def _placement_error(world: World, sd: float) -> np.ndarray:
    """This scene's error in placing the eye window: (dx, dy, log width), ``sd`` each.

    Seeded by the scene itself (its target's place, which every scene draws anew), so the
    world's stream is left as it was.
    """
    place = np.ascontiguousarray(world.state.target_pos_m, np.float64)
    entropy = np.frombuffer(place.tobytes(), np.uint32).tolist()
    return np.random.default_rng([*entropy, _PLACEMENT_KEY]).normal(0.0, sd, 3)


def eye_window_at(world: World, centre_px, distance_px: float, error=None) -> np.ndarray:
    """The eye window placed at ``centre_px`` for eyes ``distance_px`` apart (camera pixels).

    The field, ``span`` times ``distance_px`` wide, is seen through the fovea
    (:meth:`World.render_fovea`), no finer than a sensor ``zoom`` times the camera's: where the
    field holds fewer of its pixels than the window, it is averaged down to them first.
    ``error``: (dx, dy, log width) of a misplaced window, in eye distances, or None.
    """
    import cv2

    ew = world.config.eye_window
    if not ew.enabled:
        raise ValueError("the world keeps no eye window; expected eye_window.width_px and "
                         "height_px above 0")
    centre_px, distance_px = _placed(centre_px, distance_px, error)
    field_px = ew.span * distance_px
    size = (FOVEA_SUPERSAMPLE * ew.width_px, FOVEA_SUPERSAMPLE * ew.height_px)
    gray = cv2.cvtColor(world.render_fovea(centre_px, field_px, size), cv2.COLOR_RGB2GRAY)
    sensor_px = field_px * ew.zoom  # the finer sensor's pixels across the field
    if sensor_px < ew.width_px:
        coarse = (max(1, round(sensor_px)), max(1, round(sensor_px * ew.height_px / ew.width_px)))
        gray = cv2.resize(gray, coarse, interpolation=cv2.INTER_AREA)
        return cv2.resize(gray, (ew.width_px, ew.height_px), interpolation=cv2.INTER_LINEAR)
    return cv2.resize(gray, (ew.width_px, ew.height_px), interpolation=cv2.INTER_AREA)


def sockets_in_window(world: World, centre_px, distance_px: float, error=None) -> np.ndarray:
    """Where the eyeballs' centres lie in the eye window :func:`eye_window_at` cuts there.

    (2 eyes, x y) in window pixels (pixel centres at integers), the left eye first: what only
    the experimenter knows, to fit and measure the robot's socket finders. ``error``: as
    :func:`eye_window_at`'s.
    """
    ew = world.config.eye_window
    uv = _eyes_px(world)
    centre_px, distance_px = _placed(centre_px, distance_px, error)
    field_px = ew.span * distance_px
    half_px = np.array([1.0, ew.height_px / ew.width_px]) * field_px / 2
    corner = np.asarray(centre_px, float) - half_px
    return (uv - corner) * ew.width_px / field_px - 0.5


def capture_face_window(world: World, image: np.ndarray | None = None) -> np.ndarray:
    """The face window of the robot's current view (``image``, else a new render)."""
    fw = world.config.face_window
    image = world.render() if image is None else image
    return face_window(image, *face_box(world), (fw.width_px, fw.height_px))


def _cut_by_finder(images: list[np.ndarray], faces: np.ndarray, size_px) -> np.ndarray:
    """Re-cut ``faces`` in place around the faces the robot's finder finds; which were found."""
    finder = finder_for(FACE_FINDER)
    found = np.zeros(len(faces), bool)
    for i, image in enumerate(images):
        match = finder.find(image)
        if match:
            faces[i], found[i] = window_of(image, match[0], size_px), True
    if not found.any():
        raise ValueError("cut = 'finder': the face finder found no face in any recording; "
                         "expected the caregiver's face in them")
    return found


def split_evenly(n: int, k: int) -> np.ndarray:
    """The part (0 to k - 1) of each of ``n`` items cut into ``k`` contiguous parts.

    The sizes differ by at most one: the first ``n % k`` parts hold one more.
    """
    sizes = np.full(k, n // k)
    sizes[: n % k] += 1
    return np.repeat(np.arange(k), sizes)


def make_datasets(
    config: WorldConfig, n: int, seed: int, progress: Callable[[int], None] | None = None,
    caregivers: int = 1, cut: str = "box", *, stream: str = "world",
    identities: Sequence[Caregiver] | None = None,
) -> CaregiverDatasets:
    """``n`` data sets, each from a new scene, posed by ``caregivers`` people.

    In each, the robot looks at the caregiver's face, records the face window and its head angle,
    and the command that would centre the target. The data sets are split as evenly as possible
    across the caregivers, in turn (:func:`split_evenly`): caregiver 0 is the world's own
    identity (drawn from ``seed``), each next one a new identity drawn by the world
    (``World.reset(new_identity=True)``). With several caregivers the data sets name them
    (the ``caregiver`` field) and ``meta["caregivers"]`` holds each one's head size and
    colours; with one they are exactly the data sets recorded before caregivers existed.

    ``cut``: where each face window is cut. ``"box"``: around the head's projection (what only
    the experimenter knows). ``"finder"``: around the face the robot's own face finder
    finds (:data:`FACE_FINDER`), as a robot's recordings are made (``datasets import``) and as
    ``follow`` and the closed loop cut their windows; data sets whose face it does not find are
    left out (``meta["without_face"]``).

    ``stream``: the world's random stream (:class:`World`); another than ``"world"`` is kept in
    ``meta["stream"]``. ``identities``: the data sets are posed by these caregivers instead,
    split evenly in turn, in scenes drawn from the stream (new poses of known caregivers, e.g.
    :func:`caregivers_of` a recording); ``meta["caregivers"]`` names them.
    """
    if cut not in CUTS:
        raise ValueError(f"cut {cut!r}: expected one of {', '.join(CUTS)}")
    if n < 1:
        raise ValueError(f"n = {n}: expected at least one data set")
    if identities is not None:
        identities = list(identities)
        if not identities or not all(isinstance(c, Caregiver) for c in identities):
            raise ValueError("identities: expected a non-empty list of Caregiver")
        if caregivers != 1:
            raise ValueError(f"caregivers = {caregivers} with identities: expected one or the "
                             "other (the identities say how many caregivers pose)")
        caregivers = len(identities)
    if not 1 <= caregivers <= n:
        raise ValueError(f"caregivers = {caregivers}: expected 1 to n = {n} (each caregiver "
                         "poses at least one data set)")
    if cut == "finder" and config.eye_window.enabled:
        raise ValueError("cut = 'finder' with an eye window: the eye window is cut around the "
                         "caregiver's eyes as the box is; expected cut = 'box'")
    fw, ew = config.face_window, config.eye_window
    faces = np.empty((n, fw.height_px, fw.width_px), np.uint8)
    eyes = np.empty((n, *ew.kept_size_px[::-1]), np.uint8) if ew.enabled else None
    theta_face = np.empty((n, 2))
    command = np.empty((n, 2))
    target = np.empty((n, 3))
    who = split_evenly(n, caregivers)
    people, images = [], []
    with World(config, seed=seed, stream=stream) as world:
        for i in range(n):
            new_identity = i > 0 and who[i] != who[i - 1]
            if identities is not None:
                world.caregiver = identities[who[i]]
                new_identity = False
            state = world.reset(new_identity=new_identity)
            if i == 0 or who[i] != who[i - 1]:
                people.append(dataclasses.asdict(world.caregiver))
            theta_face[i] = world.face_angle_rad
            world.set_head_angle(theta_face[i])
            image = world.render()
            faces[i] = capture_face_window(world, image)
            if eyes is not None:
                eyes[i] = capture_eye_window(world)
            if cut == "finder":
                images.append(image)
            command[i] = world.kinematics.centring_angles(state.target_pos_m) - theta_face[i]
            target[i] = state.target_pos_m
            if progress is not None:
                progress(i + 1)
    meta = {
        "generator": f"jointattention {__version__}",
        "seed": seed,
        "world_config_toml": config.to_toml(),
    }
    if stream != "world":
        meta["stream"] = stream
    if cut == "finder":
        keep = _cut_by_finder(images, faces, (fw.width_px, fw.height_px))
        faces, theta_face, command, target, who = (
            a[keep] for a in (faces, theta_face, command, target, who))
        meta.update(cut="finder", face_finder=FACE_FINDER,
                    without_face=np.flatnonzero(~keep).tolist())
    if identities is not None or caregivers > 1:
        meta["caregivers"] = people
    return CaregiverDatasets(faces, theta_face, command, target, meta,
                             caregiver=None if caregivers == 1 else who, eyes=eyes)


def caregivers_of(datasets: CaregiverDatasets | str | Path,
                  world_config: WorldConfig) -> list[Caregiver]:
    """The caregivers who posed ``datasets`` (or the data-set file of that name), in order.

    From ``meta["caregivers"]`` where the data sets name them (several caregivers, or given
    identities); else the one identity of ``World(world_config, seed=meta["seed"],
    stream=meta.get("stream", "world"))``, drawn here without building the world.
    ``world_config`` must be the world they were recorded in. Give them to
    ``make_datasets(..., identities=...)`` for new poses of the same people. Data sets that do
    not say who posed them (a robot's recording) raise :class:`DatasetError`.
    """
    where = "data sets"
    if not isinstance(datasets, CaregiverDatasets):
        where, datasets = str(datasets), load(datasets)
    meta = datasets.meta
    if "caregivers" in meta:
        people = meta["caregivers"]
        if not isinstance(people, list) or not people:
            raise DatasetError(f"{where}: meta 'caregivers': expected a list of identities")
        out = []
        for i, person in enumerate(people):
            try:
                out.append(caregiver_from_dict(person))
            except ValueError as err:
                raise DatasetError(f"{where}: meta 'caregivers'[{i}]: {err}") from None
        if datasets.caregiver is not None and int(datasets.caregiver.max()) >= len(out):
            raise DatasetError(f"{where}: field 'caregiver' names caregiver "
                               f"{int(datasets.caregiver.max())}; meta 'caregivers' has "
                               f"{len(out)}")
        return out
    seed, stream = meta.get("seed"), meta.get("stream", "world")
    if datasets.n_caregivers not in (None, 1) or isinstance(seed, bool) \
            or not isinstance(seed, int) or seed < 0 or not isinstance(stream, str) or not stream:
        raise DatasetError(f"{where}: the data sets do not say who posed them (expected meta "
                           "'caregivers', or the 'seed' of jointattention datasets make); a "
                           "robot's recording names no simulated caregiver")
    return [sample_caregiver(world_config, rngs.stream(seed, stream))]  # the world's first draw
