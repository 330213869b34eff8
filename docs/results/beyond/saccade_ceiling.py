"""The oracle's ceiling when it moves as far as the saccading memory does.

The ceiling every learning curve is judged against is the oracle's: it knows the target's
direction and steps along it ``lm_step_deg`` (4 deg) at a time, and a distractor it centres on
the way ends its trial. With ``memory.saccade`` the memory moves to its recalled place in one
move, as long as visual feedback's longest (Eq. 2 to an image corner), passing over the
objects between. This script measures the oracle moving as far in one move, in the beyond
preset's world (the same 4,000 trials as its ceilings), at 5 and 10 objects.

Run from the repository: ``python docs/results/beyond/saccade_ceiling.py`` (a few seconds); it
prints a table (and writes it to ``--out``, if given). ``--quick``: 200 trials (the tests' run).
"""

from __future__ import annotations

import argparse
import dataclasses
import math
from pathlib import Path

from jointattention import load_config
from jointattention.agent.attention import largest_feedback_rad
from jointattention.experiment.cells import measure_ceiling


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, help="also write the table here")
    parser.add_argument("--quick", action="store_true", help="200 trials (the tests' run)")
    args = parser.parse_args()
    n_trials = 200 if args.quick else None  # None: the preset's ceiling trials
    config = load_config("beyond")
    world = config.world
    reach_deg = math.degrees(largest_feedback_rad(world.camera.width_px, world.camera.height_px,
                                                  config.agent.vf_gain_rad_per_px))
    far = dataclasses.replace(config, agent=dataclasses.replace(config.agent,
                                                                lm_step_deg=reach_deg))
    lines = [f"| objects | ceiling ({config.agent.lm_step_deg:g} deg a move) | "
             f"the oracle moving {reach_deg:.1f} deg a move |", "|---|---|---|"]
    for n in (5, 10):
        lines.append(f"| {n} | {measure_ceiling(config, n, n_trials):.3f} | "
                     f"{measure_ceiling(far, n, n_trials):.3f} |")
    print("\n".join(lines))
    if args.out:
        args.out.write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
