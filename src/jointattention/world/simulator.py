"""The world: one compiled MuJoCo model showing random scenes to the robot's camera."""

from __future__ import annotations

import numpy as np

from .. import rng as rngs
from .._checks import check_int
from ..agent.attention import attended_object
from ..errors import RenderingUnavailable
from . import gl
from .face import BODIES, head_colours, head_parts
from .fast import FastScene
from .identity import sample_caregiver
from .kinematics import HeadKinematics
from .look import apply_sensor
from .mjcf import WALLS, build_mjcf
from .options import N_OBJECTS, WorldConfig
from .scene import SceneState, sample_scene

__all__ = ["World"]


def _quat_yaw_pitch(yaw: float, pitch: float) -> np.ndarray:
    """Quaternion of a yaw about +z then a pitch about the yawed -x (pitch > 0 looks down)."""
    qz = np.array([np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2)])
    qx = np.array([np.cos(-pitch / 2), np.sin(-pitch / 2), 0.0, 0.0])
    out = np.empty(4)
    gl.mujoco().mju_mulQuat(out, qz, qx)
    return out


class World:
    """The simulated room: robot head, caregiver and objects, in MuJoCo.

    Args:
        config: the world's geometry, camera and variation ranges.
        seed: the seed of the world's own random stream (scenes, identities).
        stream: the name of that stream (:func:`jointattention.rng.stream`): ``"world"``, or
            ``"held-out"`` for caregivers and poses that no training world draws.
        n_objects: the objects of each scene (the MuJoCo model holds as many).

    The caregiver's identity is drawn once from the seed; :meth:`reset` draws a new scene
    (objects, target, gaze, light, look) each call. Rendering starts lazily, so a world used
    only for fast projection needs no OpenGL. MuJoCo renders with the OpenGL backend that
    ``MUJOCO_GL`` names (:mod:`.gl`: the library reads it and never sets it).
    """

    def __init__(self, config: WorldConfig | None = None, *, seed: int = 0,
                 stream: str = "world", n_objects: int = N_OBJECTS):
        if not isinstance(stream, str) or not stream:
            raise ValueError(f"stream = {stream!r}: expected a stream's name")
        self.n_objects = check_int("n_objects", n_objects, 1, 20)
        self.config = config if config is not None else WorldConfig()
        self.kinematics = HeadKinematics.from_config(self.config)
        mujoco = gl.mujoco()
        self.model = mujoco.MjModel.from_xml_string(build_mjcf(self.config, self.n_objects))
        self.data = mujoco.MjData(self.model)
        self.stream = stream
        self.rng = rngs.stream(seed, stream)
        self.caregiver = sample_caregiver(self.config, self.rng)
        self._renderer = None
        self._fovea_renderers: dict[tuple[int, int], object] = {}
        self._base_size = self.model.geom_size.copy()
        self._base_pos = self.model.body_pos.copy()
        self._base_geom_pos = self.model.geom_pos.copy()
        self._base_rgba = self.model.geom_rgba.copy()
        self._base_light_dir = self.model.light_dir.copy()
        self._noise = np.random.default_rng(0)  # the sensor noise of the scene's images
        self.state: SceneState = sample_scene(self.config, self.rng, self.caregiver,
                                              self.n_objects)
        self.set_scene(self.state)

    # -- scene ---------------------------------------------------------------------------------
    def reset(self, *, new_identity: bool = False) -> SceneState:
        """Draw and show a new scene; with ``new_identity`` a new caregiver too."""
        if new_identity:
            self.caregiver = sample_caregiver(self.config, self.rng)
        self.set_scene(sample_scene(self.config, self.rng, self.caregiver, self.n_objects))
        return self.state

    def set_scene(self, state: SceneState) -> None:
        """Show ``state``: place and colour the caregiver, the objects and the light."""
        m, d = self.model, self.data
        if state.n_objects != self.n_objects:
            raise ValueError(
                f"scene has {state.n_objects} objects; this world shows {self.n_objects}")
        self.state = state
        cg, look = state.caregiver, state.look
        for name, part in head_parts(cg).items():
            if name in BODIES:
                b = m.body(name).id
                m.body_pos[b] = self._base_pos[b] * part.pos + part.offset_m
            else:
                g = m.geom(name).id
                m.geom_size[g] = self._base_size[g] * part.size
                m.geom_pos[g] = self._base_geom_pos[g] * part.pos + part.offset_m
        for name, rgb in head_colours(cg).items():
            m.geom_rgba[m.geom(name).id] = (*rgb, 1)
        for names, factors in ((WALLS, look.wall_rgb), (("floor",), look.floor_rgb)):
            for g in (m.geom(name).id for name in names):
                m.geom_rgba[g, :3] = np.clip(self._base_rgba[g, :3] * factors, 0, 1)
        head = m.body("cg_head")
        d.mocap_pos[m.body_mocapid[head.id]] = state.head_pos_m
        d.mocap_quat[m.body_mocapid[head.id]] = _quat_yaw_pitch(*state.head_yaw_pitch_rad)
        torso = m.body("cg_torso").id
        drop = -0.64 * cg.head_scale * cg.head_height
        d.mocap_pos[m.body_mocapid[torso]] = state.head_pos_m + [0, 0.05, drop]
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
        m.light_diffuse[light] = state.light_intensity * np.array(look.light_rgb)
        m.light_dir[light] = self._base_light_dir[light] if look.light_dir is None \
            else look.light_dir
        m.vis.headlight.ambient[:] = look.ambient
        self._noise = np.random.default_rng(look.noise_seed)
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
        mujoco = gl.mujoco()
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
        """The image of ``camera``: RGB uint8 (H, W, 3), or geom ids (H, W) if ``segmentation``.

        The robot's camera (``"eye"``) gives its colour image through the scene's sensor effects
        (blur, gain, noise: :func:`~jointattention.world.look.apply_sensor`); segmentation and
        the other cameras are the render as it is.
        """
        r = self._get_renderer()
        if segmentation:
            r.enable_segmentation_rendering()
        try:
            r.update_scene(self.data, camera=camera)
            img = r.render()
        finally:
            r.disable_segmentation_rendering()
        if segmentation:
            return img[..., 0].copy()
        if camera == "eye":
            return apply_sensor(img.copy(), self.state.look, self._noise)
        return img.copy()

    def render_fovea(self, centre_px, field_width_px: float, size_px: tuple[int, int]
                     ) -> np.ndarray:
        """A part of the robot's view rendered finer: RGB uint8 (height, width, 3) of ``size_px``.

        The part is ``field_width_px`` camera pixels wide (the height in ``size_px``'s aspect),
        centred on the camera pixel ``centre_px``. It is what a camera of the same pose and a
        finer sensor sees there: the ``"fovea"`` camera's intrinsics are set to cut exactly
        that part of the image plane (the same pinhole, so the same perspective), through the
        scene's sensor effects. The eye window is cut from it
        (:func:`~.recording.capture_eye_window`); the whole view finer is :meth:`render_zoomed`.
        """
        m, kin = self.model, self.kinematics
        width, height = size_px
        cam = m.camera("fovea").id
        scale = width / field_width_px  # fovea pixels per camera pixel
        m.cam_sensorsize[cam] = size_px
        m.cam_resolution[cam] = size_px
        off_x, off_y = (np.asarray(centre_px, float) - kin.centre_px) * scale
        m.cam_intrinsic[cam] = [kin.focal_px * scale, kin.focal_px * scale, off_x, off_y]
        key = (height, width)
        if key not in self._fovea_renderers:
            # a fovea larger than the camera's buffer gets a buffer its size; the model keeps
            # the camera's, so the eye camera's renders still clear no more than its image
            buffer = m.vis.global_
            kept = (int(buffer.offwidth), int(buffer.offheight))
            buffer.offwidth, buffer.offheight = max(kept[0], width), max(kept[1], height)
            try:
                self._fovea_renderers[key] = gl.renderer(m, height, width)
            finally:
                buffer.offwidth, buffer.offheight = kept
        r = self._fovea_renderers[key]
        r.update_scene(self.data, camera="fovea")
        return apply_sensor(r.render().copy(), self.state.look, self._noise)

    def render_zoomed(self, zoom: float) -> np.ndarray:
        """The robot's whole view through the fovea, ``zoom`` times the camera's resolution.

        RGB uint8 (round(zoom * height), round(zoom * width), 3): what a camera of the same
        pose with a sensor ``zoom`` times finer sees (:meth:`render_fovea` over the whole
        image), the frames a model that reads the eyes takes.
        """
        kin = self.kinematics
        return self.render_fovea(kin.centre_px, kin.width_px,
                                 (round(zoom * kin.width_px), round(zoom * kin.height_px)))

    def object_geom_ids(self) -> np.ndarray:
        """The MuJoCo geom id of each object (to read segmentation images)."""
        return np.array([self.model.geom(f"obj{i}").id for i in range(self.state.n_objects)])

    def _get_renderer(self):
        if self._renderer is None:
            kin = self.kinematics
            try:
                self._renderer = gl.renderer(self.model, kin.height_px, kin.width_px)
            except RenderingUnavailable:
                raise
            except Exception as err:  # the GL stack raises many kinds
                raise RenderingUnavailable(
                    f"cannot start off-screen OpenGL (MUJOCO_GL={gl.backend()}): {err}; "
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
        """Free the renderers' OpenGL contexts."""
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
        for r in self._fovea_renderers.values():
            r.close()
        self._fovea_renderers.clear()

    def __enter__(self) -> World:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
