"""Head kinematics and the pinhole camera: where the robot looks, and where things appear.

Frames. The world frame has its origin at the intersection of the pan and tilt axes, x to the
robot's right, y forward, z up. Pan turns the head about -z (positive turns right), tilt about
the panned x axis (positive looks up). The camera's optical centre sits at ``offset_m`` in the
head frame, so it moves when the head turns: the nonlinearity the paper names.

Pixels. ``u`` grows to the right, ``v`` downward; pixel centres lie on integers, so the image
centre is ``((W - 1) / 2, (H - 1) / 2)``. This is OpenCV's convention, and MuJoCo renders the
same pinhole (its frustum spans the pixel edges ``[0, W]``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._arrays import floats, rows
from .._jit import jit
from ..agent.detections import equal_area_radius
from .options import WorldConfig

__all__ = ["BEHIND", "CENTRED", "INSIDE_LATERAL", "INSIDE_VERTICAL", "HeadKinematics",
           "Unreachable", "angle_rad", "camera_point", "centring_angles", "direction",
           "forward_axis", "pixel_px", "project_spheres_into", "rotation_into", "rotation_matrix",
           "separation_rad", "sphere_area_px"]


class Unreachable(ValueError):
    """No head angle centres the point (it is too close, or the camera cannot face it)."""


def direction(pan_rad, tilt_rad) -> np.ndarray:
    """Unit vectors (..., 3) toward directions (pan right, tilt up) from the origin."""
    pan_rad, tilt_rad = np.asarray(pan_rad), np.asarray(tilt_rad)
    return np.stack([np.sin(pan_rad) * np.cos(tilt_rad), np.cos(pan_rad) * np.cos(tilt_rad),
                     np.sin(tilt_rad)], axis=-1)


def angle_rad(a, b) -> np.ndarray:
    """Angles (rad) between each vector of ``a`` (..., k) and the vector ``b`` (k,)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    # sums of products, not ``a @ b``: BLAS fuses multiply-adds on some CPUs, not on others
    cos = (a * b).sum(axis=-1) / (np.sqrt((a * a).sum(axis=-1)) * np.sqrt((b * b).sum()))
    return np.arccos(np.clip(cos, -1.0, 1.0))


@jit
def separation_rad(a_m: np.ndarray, b_m: np.ndarray) -> float:
    """The angle between two points seen from the origin (the robot's head).

    How far from her target the robot looked, as the caregiver judges it (the developmental
    model: docs/neighbours.md).
    """
    dot = a_m[0] * b_m[0] + a_m[1] * b_m[1] + a_m[2] * b_m[2]
    norms = math.sqrt((a_m[0] ** 2 + a_m[1] ** 2 + a_m[2] ** 2)
                      * (b_m[0] ** 2 + b_m[1] ** 2 + b_m[2] ** 2))
    return math.acos(min(max(dot / norms, -1.0), 1.0))


@jit
def rotation_matrix(pan_rad: float, tilt_rad: float) -> np.ndarray:
    """Head orientation: columns are the head's right, forward and up axes in the world."""
    rot = np.empty((3, 3))
    rotation_into(pan_rad, tilt_rad, rot)
    return rot


@jit
def rotation_into(pan_rad: float, tilt_rad: float, rot: np.ndarray) -> None:
    """:func:`rotation_matrix` written into ``rot`` (3, 3): a loop's look allocates nothing."""
    cp, sp = math.cos(pan_rad), math.sin(pan_rad)
    ct, st = math.cos(tilt_rad), math.sin(tilt_rad)
    # (rotation about -z by pan) @ (rotation about +x by tilt), multiplied out
    rot[0, 0], rot[0, 1], rot[0, 2] = cp, sp * ct, -sp * st
    rot[1, 0], rot[1, 1], rot[1, 2] = -sp, cp * ct, -cp * st
    rot[2, 0], rot[2, 1], rot[2, 2] = 0.0, st, ct


@jit
def forward_axis(pan_rad: float, tilt_rad: float) -> tuple[float, float, float]:
    """The head's forward axis in the world: :func:`rotation_matrix`'s middle column.

    The same products, without a matrix: a placement's every candidate asks it.
    """
    return (math.sin(pan_rad) * math.cos(tilt_rad), math.cos(pan_rad) * math.cos(tilt_rad),
            math.sin(tilt_rad))


@jit
def _along(p: np.ndarray, a0: float, a1: float, a2: float, offset_m: float) -> float:
    """World point ``p`` along the head axis (a0, a1, a2), less the camera's offset on it."""
    return p[0] * a0 + p[1] * a1 + p[2] * a2 - offset_m


@jit
def camera_point(point_m, rot, offset_m) -> tuple[float, float, float]:
    """A world point in the camera frame: (right, depth, up), the columns of ``rot``."""
    return (_along(point_m, rot[0, 0], rot[1, 0], rot[2, 0], offset_m[0]),
            _along(point_m, rot[0, 1], rot[1, 1], rot[2, 1], offset_m[1]),
            _along(point_m, rot[0, 2], rot[1, 2], rot[2, 2], offset_m[2]))


@jit
def project_spheres_into(points_m, radii_m, rot, offset_m, focal_px, cx_px, cy_px,
                         uv, depth, area) -> None:
    """Pixel positions, depths and image areas of spheres, written into ``uv``, ``depth``, ``area``.

    Points behind the camera get NaN positions and areas (:func:`pixel_px`,
    :func:`sphere_area_px`).
    """
    for i in range(points_m.shape[0]):
        x, d, z = camera_point(points_m[i], rot, offset_m)
        uv[i, 0], uv[i, 1] = pixel_px(x, d, z, focal_px, cx_px, cy_px)
        depth[i] = d
        area[i] = sphere_area_px(x, d, z, radii_m[i], focal_px)


@jit
def pixel_px(x, d, z, focal_px, cx_px, cy_px) -> tuple[float, float]:
    """The pixel (u, v) of a point at camera coordinates (x, d, z); NaN behind the camera."""
    if not d > 0:
        return np.nan, np.nan
    return cx_px + focal_px * (x / d), cy_px + focal_px * (-z / d)


@jit
def sphere_area_px(x, d, z, radius_m, focal_px) -> float:
    """The image area of a sphere centred at camera coordinates (x, d, z); NaN behind.

    A sphere of angular radius b seen at angle a off the optical axis images as an ellipse
    with semi-axes f sin(b) cos(b) / (cos^2 a - sin^2 b) (radial) and
    f sin(b) / sqrt(cos^2 a - sin^2 b): off-axis spheres look larger than on-axis ones.
    """
    if not d > 0:
        return np.nan
    dist2 = x * x + d * d + z * z
    sin2_b = radius_m * radius_m / dist2
    denom = d * d / dist2 - sin2_b
    if denom > 0:
        return math.pi * focal_px * focal_px * sin2_b * np.sqrt(1 - sin2_b) / denom**1.5
    return np.nan


# centring_angles' status: solved, or why not
CENTRED, INSIDE_LATERAL, INSIDE_VERTICAL, BEHIND = 0, 1, 2, 3


@jit
def centring_angles(point_m: np.ndarray, offset_m: np.ndarray) -> tuple[float, float, int]:
    """The head angle (pan, tilt) that puts ``point_m`` on the optical axis, and a status.

    Solved in closed form for the offset camera: the lateral offset fixes pan through
    ``x' = o_x`` after un-panning, then the vertical offset fixes tilt through ``z'' = o_z``.
    The status is :data:`CENTRED` or why no angle does it. Joint limits are not applied.
    """
    px, py, pz = point_m[0], point_m[1], point_m[2]
    ox, oz = offset_m[0], offset_m[2]
    r = math.hypot(px, py)
    if r <= abs(ox):
        return np.nan, np.nan, INSIDE_LATERAL
    # x' = cos(pan) px - sin(pan) py = r cos(pan + gamma) must equal o_x.
    gamma, spread = math.atan2(py, px), math.acos(ox / r)
    p1, p2 = -gamma + spread, -gamma - spread
    p1, p2 = math.atan2(math.sin(p1), math.cos(p1)), math.atan2(math.sin(p2), math.cos(p2))
    # The right branch leaves the point in front (y' > 0 after un-panning).
    front1 = math.sin(p1) * px + math.cos(p1) * py
    pan = p1 if front1 >= math.sin(p2) * px + math.cos(p2) * py else p2
    y1 = math.sin(pan) * px + math.cos(pan) * py
    rho = math.hypot(y1, pz)
    if rho <= abs(oz):
        return np.nan, np.nan, INSIDE_VERTICAL
    tilt = math.atan2(pz, y1) - math.asin(oz / rho)
    f0, f1, f2 = forward_axis(pan, tilt)
    if _along(point_m, f0, f1, f2, offset_m[1]) <= 0:  # the depth, as camera_point sums it
        return np.nan, np.nan, BEHIND
    return pan, tilt, CENTRED


@dataclass(frozen=True)
class HeadKinematics:
    """The pan/tilt head and its offset pinhole camera (world geometry, not the robot's)."""

    offset_m: tuple[float, float, float]
    width_px: int
    height_px: int
    fov_deg: float
    pan_limits_rad: tuple[float, float]
    tilt_limits_rad: tuple[float, float]

    @classmethod
    def from_config(cls, world: WorldConfig) -> HeadKinematics:
        """The head and camera of ``world``."""
        cam, head = world.camera, world.head
        return cls(
            offset_m=cam.offset_m,
            width_px=cam.width_px,
            height_px=cam.height_px,
            fov_deg=cam.fov_deg,
            pan_limits_rad=tuple(np.deg2rad(head.pan_limits_deg)),
            tilt_limits_rad=tuple(np.deg2rad(head.tilt_limits_deg)),
        )

    @property
    def focal_px(self) -> float:
        """Focal length in pixels, from the horizontal field of view."""
        return (self.width_px / 2) / np.tan(np.deg2rad(self.fov_deg) / 2)

    @property
    def fovy_deg(self) -> float:
        """Vertical field of view (what MuJoCo's camera takes)."""
        return float(np.rad2deg(2 * np.arctan((self.height_px / 2) / self.focal_px)))

    @property
    def centre_px(self) -> np.ndarray:
        """The image centre (c_x, c_y) of the paper's Eq. 2 and 3."""
        return np.array([(self.width_px - 1) / 2, (self.height_px - 1) / 2])

    def rotation(self, theta_rad) -> np.ndarray:
        """Head orientation for head angle ``theta_rad = (pan, tilt)``."""
        return rotation_matrix(float(theta_rad[0]), float(theta_rad[1]))

    def camera_position(self, theta_rad) -> np.ndarray:
        """The optical centre in the world for head angle ``theta_rad``."""
        return self.rotation(theta_rad) @ np.asarray(self.offset_m)

    def gaze_direction(self, theta_rad) -> np.ndarray:
        """Unit vector of the optical axis in the world for head angle ``theta_rad``."""
        return self.rotation(theta_rad)[:, 1]

    def project_spheres(self, points_m, radii_m, theta_rad):
        """Pixel positions (N, 2), depths (N,) and exact image areas (N,) of spheres.

        Points behind the camera get NaN positions and areas (see
        :func:`project_spheres_into`).
        """
        points = rows("points_m", points_m, 3)
        radii = floats("radii_m", radii_m, None)
        radii = np.full(len(points), radii) if radii.ndim == 0 else floats(
            "radii_m", radii, (len(points),))
        n = len(points)
        uv, depth, area = np.empty((n, 2)), np.empty(n), np.empty(n)
        cx, cy = self.centre_px
        project_spheres_into(points, radii, self.rotation(theta_rad), np.asarray(self.offset_m),
                             float(self.focal_px), cx, cy, uv, depth, area)
        return uv, depth, area

    def in_image(self, uv: np.ndarray, depth: np.ndarray) -> np.ndarray:
        """Whether each projected point lies in front of the camera and inside the image."""
        w, h = self.width_px, self.height_px
        with np.errstate(invalid="ignore"):
            return (depth > 0) & (uv[:, 0] >= -0.5) & (uv[:, 0] <= w - 0.5) & (
                uv[:, 1] >= -0.5) & (uv[:, 1] <= h - 0.5)

    def project(self, points_m, theta_rad) -> tuple[np.ndarray, np.ndarray]:
        """Pixel positions (N, 2) of world points and their depths (N,) along the optical axis.

        Points behind the camera get NaN positions.
        """
        uv, depth, _ = self.project_spheres(points_m, 0.0, theta_rad)
        return uv, depth

    def apparent_area_px(self, points_m, radii_m, theta_rad) -> np.ndarray:
        """Exact image area in pixels of spheres centred at ``points_m``."""
        return self.project_spheres(points_m, radii_m, theta_rad)[2]

    def apparent_radius_px(self, points_m, radii_m, theta_rad) -> np.ndarray:
        """Radius of the circle with the same image area as each sphere (exact on the axis)."""
        return equal_area_radius(self.apparent_area_px(points_m, radii_m, theta_rad))

    def within_limits(self, theta_rad) -> bool:
        """Whether ``theta_rad`` lies inside the pan and tilt joint ranges."""
        (p0, p1), (t0, t1) = self.pan_limits_rad, self.tilt_limits_rad
        return bool(p0 <= theta_rad[0] <= p1 and t0 <= theta_rad[1] <= t1)

    def clip(self, theta_rad) -> np.ndarray:
        """``theta_rad`` clipped to the joint ranges."""
        lo = (self.pan_limits_rad[0], self.tilt_limits_rad[0])
        hi = (self.pan_limits_rad[1], self.tilt_limits_rad[1])
        return np.clip(np.asarray(theta_rad, dtype=float), lo, hi)

    def centring_angles(self, point_m) -> np.ndarray:
        """The head angle (pan, tilt) that puts ``point_m`` on the optical axis.

        Joint limits are not applied; see :meth:`within_limits`. Raises :class:`Unreachable`
        if no head angle does it (see :func:`centring_angles`).
        """
        point = floats("point_m", point_m, (3,))
        pan, tilt, status = centring_angles(point, np.asarray(self.offset_m, dtype=float))
        if status == CENTRED:
            return np.array([pan, tilt])
        where = {INSIDE_LATERAL: "is inside the camera's lateral offset",
                 INSIDE_VERTICAL: "is inside the camera's vertical offset",
                 BEHIND: "lies behind the camera"}[status]
        raise Unreachable(f"point {point_m} {where}")
