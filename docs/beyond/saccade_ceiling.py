"""The oracle's ceiling when it moves as far as the saccading memory does.

The ceiling every learning curve is judged against is the oracle's: it knows the target's
direction and steps along it ``lm_step_deg`` (4 deg) at a time, and a distractor it centres on
the way ends its trial. With ``memory.saccade`` the memory moves to its recalled place in one
move, as long as visual feedback's longest (Eq. 2 to an image corner), passing over the
objects between. This script measures the oracle moving as far in one move, in the beyond
preset's world (the same 4,000 trials as its ceilings), at 5 and 10 objects.

Run from the repository: ``python docs/beyond/saccade_ceiling.py`` (a few seconds); it prints
a table.
"""

from __future__ import annotations

import dataclasses
import math

from jointattention import load_config
from jointattention.agent.attention import largest_feedback_rad
from jointattention.experiment.cells import measure_ceiling


def main() -> None:
    config = load_config("beyond")
    world = config.world
    reach_deg = math.degrees(largest_feedback_rad(world.camera.width_px, world.camera.height_px,
                                                  config.agent.vf_gain_rad_per_px))
    far = dataclasses.replace(config, agent=dataclasses.replace(config.agent,
                                                                lm_step_deg=reach_deg))
    print(f"| objects | ceiling ({config.agent.lm_step_deg:g} deg a move) | "
          f"the oracle moving {reach_deg:.1f} deg a move |")
    print("|---|---|---|")
    for n in (5, 10):
        print(f"| {n} | {measure_ceiling(config, n):.3f} | {measure_ceiling(far, n):.3f} |")


if __name__ == "__main__":
    main()
