"""Claims and final success of the readings whose cells are all done.

For a partly run ``jointattention reproduce --preset ablation-paper --out runs/ablation-paper``.

python docs/ablation-paper/summarise_partial.py runs/ablation-paper runs/paper/ceilings.json
"""

import dataclasses
import json
import sys
from pathlib import Path

from jointattention.analysis.claims import check_claims, claims_table
from jointattention.analysis.curves import condition_curves
from jointattention.analysis.metrics import final_success, mean_interval
from jointattention.config import load_config
from jointattention.experiment.results import cell_path

out, ceilings = Path(sys.argv[1]), json.loads(Path(sys.argv[2]).read_text())
cfg = load_config(out / "config.toml")
exp = cfg.experiment
done = tuple(c for c in exp.conditions
             if all(cell_path(out, c.name, i).exists() for i in range(exp.n_seeds)))
cfg = dataclasses.replace(cfg, experiment=dataclasses.replace(exp, conditions=done))
curves = condition_curves(out, cfg)
print("| condition | final success | 95% interval | seeds' range | first bin |")
print("|---|---|---|---|---|")
for name, (_, per_seed) in curves.items():
    finals = [final_success(c) for c in per_seed]
    mean, lo, hi = (float(v[0]) for v in mean_interval([[f] for f in finals]))
    print(f"| {name} | {mean:.3f} | {lo:.3f} to {hi:.3f} | {min(finals):.2f} to "
          f"{max(finals):.2f} | {per_seed[:, 0].mean():.3f} |")
print()
readings = {c.name.rsplit("-", 1)[0] for c in done}
complete = {r for r in readings if sum(c.name.startswith(r + "-") for c in done) == 4}
keep = tuple(c for c in done if c.name.rsplit("-", 1)[0] in complete)
cfg = dataclasses.replace(cfg, experiment=dataclasses.replace(exp, conditions=keep))
claims = check_claims(cfg, {k: curves[k] for k in (c.name for c in keep)}, ceilings)
print(claims_table(claims).to_markdown(), end="")
