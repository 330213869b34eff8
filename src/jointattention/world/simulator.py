"""The world: one compiled MuJoCo model showing random scenes to the robot's camera."""

from __future__ import annotations

import numpy as np

from .. import rng as rngs
from ..agent.attention import attended_object
from ..config import WorldConfig
from ..errors import RenderingUnavailable
from . import _gl
from .fast import FastScene
from .kinematics import HeadKinematics
from .mjcf import build_mjcf
from .scene import SceneState, sample_caregiver, sample_scene

__all__ = ["World"]


def _quat_yaw_pitch(yaw: float, pitch: float) -> np.ndarray:
    """Quaternion of a yaw about +z then a pitch about the yawed -x (pitch > 0 looks down)."""
    qz = np.array([np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2)])
    qx = np.array([np.cos(-pitch / 2), np.sin(-pitch / 2), 0.0, 0.0])
    out = np.empty(4)
    _gl.mujoco().mju_mulQuat(out, qz, qx)
    return out


class World:
    """The simulated room: robot head, caregiver and objects, in MuJoCo.

    Args:
        config: the world's geometry, camera and variation ranges.
        seed: the seed of the world's own random stream (scenes, identities).

    The caregiver's identity is drawn once from the seed; :meth:`reset` draws a new scene
    (objects, target, gaze, light) each call. Rendering starts lazily, so a world used only
    for fast projection needs no OpenGL. The first world imports MuJoCo, after choosing its
    off-screen OpenGL backend (``MUJOCO_GL``: EGL, else OSMesa) unless the user set it.
    """

    def __init__(self, config: WorldConfig | None = None, *, seed: int = 0):
        self.config = config if config is not None else WorldConfig()
        self.kinematics = HeadKinematics.from_config(self.config)
        mujoco = _gl.mujoco()
        self.model = mujoco.MjModel.from_xml_string(build_mjcf(self.config))
        self.data = mujoco.MjData(self.model)
        self.rng = rngs.stream(seed, "world")
        self.caregiver = sample_caregiver(self.config, self.rng)
        self._renderer = None
        self._base_size = self.model.geom_size.copy()
        self._base_pos = self.model.body_pos.copy()
        self._base_geom_pos = self.model.geom_pos.copy()
        self.state: SceneState = sample_scene(self.config, self.rng, self.caregiver)
        self.set_scene(self.state)

    # -- scene ---------------------------------------------------------------------------------
    def reset(self, *, new_identity: bool = False) -> SceneState:
        """Draw and show a new scene; with ``new_identity`` a new caregiver too."""
        if new_identity:
            self.caregiver = sample_caregiver(self.config, self.rng)
        self.set_scene(sample_scene(self.config, self.rng, self.caregiver))
        return self.state

    def set_scene(self, state: SceneState) -> None:
        """Show ``state``: place and colour the caregiver, the objects and the light."""
        m, d = self.model, self.data
        if state.n_objects != self.config.objects.n_objects:
            raise ValueError(
                f"scene has {state.n_objects} objects; this world shows "
                f"{self.config.objects.n_objects}"
            )
        self.state = state
        cg = state.caregiver
        head = m.body("cg_head")
        head_geoms = np.flatnonzero(m.geom_bodyid == head.id)
        eye_bodies = [m.body(f"cg_eye_{s}").id for s in "lr"]
        for g in head_geoms:
            m.geom_size[g] = self._base_size[g] * cg.head_scale
            m.geom_pos[g] = self._base_geom_pos[g] * cg.head_scale
        for b in eye_bodies:
            m.body_pos[b] = self._base_pos[b] * cg.head_scale
            for g in np.flatnonzero(m.geom_bodyid == b):
                m.geom_size[g] = self._base_size[g] * cg.head_scale
                m.geom_pos[g] = self._base_geom_pos[g] * cg.head_scale
        m.geom_rgba[m.geom("cg_skin").id] = (*cg.skin_rgb, 1)
        m.geom_rgba[m.geom("cg_nose").id] = (*(np.array(cg.skin_rgb) * 0.9), 1)
        m.geom_rgba[m.geom("cg_mouth").id] = (*(np.array(cg.skin_rgb) * [0.6, 0.3, 0.3]), 1)
        for name in ("cg_hair", "cg_brow_l", "cg_brow_r"):
            m.geom_rgba[m.geom(name).id] = (*cg.hair_rgb, 1)
        m.geom_rgba[m.geom("cg_torso").id] = (*cg.shirt_rgb, 1)
        m.geom_rgba[m.geom("cg_neck").id] = (*cg.skin_rgb, 1)
        d.mocap_pos[m.body_mocapid[head.id]] = state.head_pos_m
        d.mocap_quat[m.body_mocapid[head.id]] = _quat_yaw_pitch(*state.head_yaw_pitch_rad)
        torso = m.body("cg_torso").id
        d.mocap_pos[m.body_mocapid[torso]] = state.head_pos_m + [0, 0.05, -0.64 * cg.head_scale]
        eye_quat = _quat_yaw_pitch(*state.eye_yaw_pitch_rad)
        for s in "lr":
            d.qpos[m.jnt_qposadr[m.joint(f"cg_eye_{s}").id] :][:4] = eye_quat
        for i in range(state.n_objects):
            body, geom = m.body(f"obj{i}").id, m.geom(f"obj{i}").id
            d.mocap_pos[m.body_mocapid[body]] = state.object_pos_m[i]
            m.geom_size[geom, 0] = state.object_radius_m[i]
            m.geom_rbound[geom] = state.object_radius_m[i]
            m.geom_rgba[geom] = (*state.object_rgb[i], 1)
        light = m.light("key").id
        m.light_pos[light] = state.light_pos_m
        m.light_diffuse[light] = state.light_intensity
        self._forward()

    # -- the robot's head ----------------------------------------------------------------------
    @property
    def head_angle_rad(self) -> np.ndarray:
        """The current head angle (pan, tilt)."""
        m = self.model
        return np.array([self.data.qpos[m.jnt_qposadr[m.joint(j).id]] for j in ("pan", "tilt")])

    def set_head_angle(self, theta_rad) -> None:
        """Turn the head to ``theta_rad`` (clipped to the joint limits)."""
        theta = self.kinematics.clip(theta_rad)
        m = self.model
        for j, value in zip(("pan", "tilt"), theta, strict=True):
            self.data.qpos[m.jnt_qposadr[m.joint(j).id]] = value
        self._forward()

    def _forward(self) -> None:
        mujoco = _gl.mujoco()
        mujoco.mj_kinematics(self.model, self.data)
        mujoco.mj_camlight(self.model, self.data)

    @property
    def face_angle_rad(self) -> np.ndarray:
        """The head angle at which the robot looks straight at the caregiver's face."""
        return self.kinematics.centring_angles(self.state.head_pos_m)

    # -- seeing --------------------------------------------------------------------------------
    def fast_scene(self) -> FastScene:
        """The scene's objects as the fast detector sees them (no rendering)."""
        s = self.state
        return FastScene(self.kinematics, s.object_pos_m, s.object_radius_m, s.target_index,
                         np.zeros(s.n_objects))

    def render(self, camera: str = "eye", *, segmentation: bool = False) -> np.ndarray:
        """The image of ``camera``: RGB uint8 (H, W, 3), or geom ids (H, W) if ``segmentation``."""
        r = self._get_renderer()
        if segmentation:
            r.enable_segmentation_rendering()
        try:
            r.update_scene(self.data, camera=camera)
            img = r.render()
        finally:
            r.disable_segmentation_rendering()
        return img[..., 0].copy() if segmentation else img.copy()

    def object_geom_ids(self) -> np.ndarray:
        """The MuJoCo geom id of each object (to read segmentation images)."""
        return np.array([self.model.geom(f"obj{i}").id for i in range(self.state.n_objects)])

    def _get_renderer(self):
        if self._renderer is None:
            kin = self.kinematics
            try:
                self._renderer = _gl.renderer(self.model, kin.height_px, kin.width_px)
            except RenderingUnavailable:
                raise
            except Exception as err:  # the GL stack raises many kinds
                raise RenderingUnavailable(
                    f"cannot start off-screen OpenGL (MUJOCO_GL={_gl.choose_backend()}): {err}; "
                    "expected EGL (libegl1) or OSMesa (libosmesa6, with MUJOCO_GL=osmesa)"
                ) from None
        return self._renderer

    # -- ground truth --------------------------------------------------------------------------
    @property
    def target_index(self) -> int:
        """The object the caregiver attends to."""
        return self.state.target_index

    def object_at_centre(self, radius_px: float, theta_rad=None) -> int | None:
        """The object the internal evaluator would fire on, else None.

        Eq. 3 with radius ``radius_px``, at ``theta_rad`` (default: the current angle).
        """
        theta = self.head_angle_rad if theta_rad is None else theta_rad
        scene = self.fast_scene()
        i = attended_object(scene.observe(theta), radius_px)
        return None if i is None else int(scene.visible_ids[i])

    def close(self) -> None:
        """Free the renderer's OpenGL context."""
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None

    def __enter__(self) -> World:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
