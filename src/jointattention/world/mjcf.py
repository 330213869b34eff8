"""The MuJoCo scene, built in code (MJCF): robot head, caregiver, objects, lights, room.

Sizes and colours written here are the caregiver's *base* identity; :mod:`.simulator`
rescales and recolours them per scene through the compiled model, so that one compiled model
serves every scene of a world.
"""

from __future__ import annotations

from .kinematics import HeadKinematics
from .options import WorldConfig

__all__ = ["CAREGIVER_PARTS", "EYE_POS_M", "EYE_RADIUS_M", "FOVEA_SUPERSAMPLE",
           "HEADLIGHT_AMBIENT", "HEAD_RADII_M", "KEY_LIGHT_DIR", "PUPIL_RADIUS_M", "PUPIL_RGB",
           "WALLS", "build_mjcf"]

# The caregiver's head ellipsoid (half width, half depth, half height) at scale 1.
HEAD_RADII_M = (0.075, 0.085, 0.105)

# Caregiver parts fixed to the head: name -> (geom type, size, position in the head frame,
# colour role). The face looks along -y (toward the robot) at zero yaw and pitch.
CAREGIVER_PARTS = {
    "skin": ("ellipsoid", HEAD_RADII_M, (0.0, 0.0, 0.0), "skin"),
    "hair": ("ellipsoid", (0.081, 0.084, 0.088), (0.0, 0.014, 0.033), "hair"),
    "nose": ("ellipsoid", (0.013, 0.028, 0.02), (0.0, -0.084, -0.01), "skin_dark"),
    "mouth": ("ellipsoid", (0.026, 0.008, 0.008), (0.0, -0.072, -0.05), "lips"),
    "brow_l": ("box", (0.016, 0.004, 0.0035), (-0.031, -0.077, 0.036), "hair"),
    "brow_r": ("box", (0.016, 0.004, 0.0035), (0.031, -0.077, 0.036), "hair"),
}
EYE_POS_M = {"l": (-0.03, -0.066, 0.017), "r": (0.03, -0.066, 0.017)}
EYE_RADIUS_M = 0.0145
PUPIL_RADIUS_M = 0.0075
PUPIL_RGB = (0.06, 0.05, 0.05)  # the iris and pupil, one sphere: the default (darkest) iris
HEADLIGHT_AMBIENT = 0.4  # the ambient light's default strength
KEY_LIGHT_DIR = (-0.1, 0.3, -1.0)  # the key light's default direction
FOVEA_SUPERSAMPLE = 2  # the fovea renders its window this many times finer, then averages
WALLS = ("wall_back", "wall_left", "wall_right")


def _vec(v) -> str:
    return " ".join(f"{x:.6g}" for x in v)


def build_mjcf(world: WorldConfig, n_objects: int) -> str:
    """The MJCF text of the world's scene, with ``n_objects`` object bodies."""
    kin = HeadKinematics.from_config(world)
    cam = world.camera
    pan_lo, pan_hi = world.head.pan_limits_deg
    tilt_lo, tilt_hi = world.head.tilt_limits_deg
    parts = "\n".join(
        f'        <geom name="cg_{name}" type="{kind}" size="{_vec(size)}" pos="{_vec(pos)}"'
        f' material="mat_cg"/>'
        for name, (kind, size, pos, _) in CAREGIVER_PARTS.items()
    )
    eyes = "\n".join(
        f'        <body name="cg_eye_{s}" pos="{_vec(pos)}">\n'
        f'          <joint name="cg_eye_{s}" type="ball"/>\n'
        f'          <inertial pos="0 0 0" mass="0.01" diaginertia="1e-6 1e-6 1e-6"/>\n'
        f'          <geom name="cg_eyeball_{s}" type="sphere" size="{EYE_RADIUS_M}"'
        f' rgba="0.95 0.95 0.93 1"/>\n'
        f'          <geom name="cg_pupil_{s}" type="sphere" size="{PUPIL_RADIUS_M}"'
        f' pos="0 {-(EYE_RADIUS_M - PUPIL_RADIUS_M * 0.45):.6g} 0" rgba="{_vec(PUPIL_RGB)} 1"/>\n'
        f"        </body>"
        for s, pos in EYE_POS_M.items()
    )
    objects = "\n".join(
        f'    <body name="obj{i}" mocap="true" pos="0 0.6 0">\n'
        f'      <geom name="obj{i}" type="sphere" size="0.03" material="mat_obj"/>\n'
        f"    </body>"
        for i in range(n_objects)
    )
    # the off-screen buffer is the camera's image, no larger: each frame clears all of it
    # (or the fovea's, when that is larger: World.render_fovea)
    fovea = world.eye_window
    buffer = (max(cam.width_px, FOVEA_SUPERSAMPLE * fovea.width_px),
              max(cam.height_px, FOVEA_SUPERSAMPLE * fovea.height_px))
    return f"""<mujoco model="jointattention">
  <compiler angle="degree"/>
  <option gravity="0 0 0"/>
  <visual>
    <global offwidth="{buffer[0]}" offheight="{buffer[1]}"/>
    <headlight ambient="{_vec([HEADLIGHT_AMBIENT] * 3)}" diffuse="0.25 0.25 0.25" specular="0 0 0"/>
    <quality shadowsize="0" offsamples="{cam.antialias_samples}"
             numslices="{cam.sphere_slices}" numstacks="{cam.sphere_stacks}"/>
  </visual>
  <default>
    <geom contype="0" conaffinity="0"/>
  </default>
  <asset>
    <material name="mat_cg" specular="0.05" shininess="0.1"/>
    <material name="mat_obj" specular="0.2" shininess="0.3"/>
    <material name="mat_room" specular="0" shininess="0"/>
  </asset>
  <worldbody>
    <light name="key" pos="0.3 0.2 1.6" dir="{_vec(KEY_LIGHT_DIR)}" diffuse="0.7 0.7 0.7"
           specular="0.1 0.1 0.1" castshadow="false"/>
    <geom name="floor" type="plane" size="4 4 0.1" pos="0 0 -1.1" rgba="0.42 0.40 0.37 1"
          material="mat_room"/>
    <geom name="wall_back" type="box" size="4 0.05 2.5" pos="0 2.6 0"
          rgba="0.62 0.63 0.60 1" material="mat_room"/>
    <geom name="wall_left" type="box" size="0.05 4 2.5" pos="-2.2 0 0"
          rgba="0.58 0.57 0.55 1" material="mat_room"/>
    <geom name="wall_right" type="box" size="0.05 4 2.5" pos="2.2 0 0"
          rgba="0.58 0.57 0.55 1" material="mat_room"/>
    <camera name="overview" pos="0.9 -1.3 0.9" xyaxes="0.83 0.56 0 -0.22 0.33 0.92"
            fovy="55"/>
    <body name="pan_link">
      <inertial pos="0 0 0" mass="1" diaginertia="0.01 0.01 0.01"/>
      <joint name="pan" type="hinge" axis="0 0 -1" range="{pan_lo} {pan_hi}" limited="true"/>
      <body name="tilt_link">
        <inertial pos="0 0 0" mass="0.5" diaginertia="0.005 0.005 0.005"/>
        <joint name="tilt" type="hinge" axis="1 0 0" range="{tilt_lo} {tilt_hi}"
               limited="true"/>
        <camera name="eye" pos="{_vec(cam.offset_m)}" xyaxes="1 0 0 0 0 1"
                fovy="{kin.fovy_deg:.9g}"/>
        <camera name="fovea" pos="{_vec(cam.offset_m)}" xyaxes="1 0 0 0 0 1"
                fovy="{kin.fovy_deg:.9g}"/>
      </body>
    </body>
    <body name="cg_torso" mocap="true" pos="0 1.05 -0.45">
      <geom name="cg_torso" type="capsule" size="0.17 0.25" rgba="0.35 0.38 0.45 1"
            material="mat_cg"/>
      <geom name="cg_neck" type="capsule" size="0.045 0.08" pos="0 -0.02 0.42"
            rgba="0.8 0.6 0.5 1" material="mat_cg"/>
    </body>
    <body name="cg_head" mocap="true" pos="0 1 0.05">
{parts}
{eyes}
    </body>
{objects}
  </worldbody>
</mujoco>
"""
