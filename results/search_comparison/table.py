#!/usr/bin/env python3
"""Table of results/search_comparison/*.json (written by regenerate.sh): energy found and
evaluations spent by each refinement, per shipped example."""
import glob, json, os

here = os.path.dirname(os.path.abspath(__file__))
rows = {}
for f in sorted(glob.glob(os.path.join(here, "*.json"))):
    name = os.path.basename(f)[:-5]
    job, search = name.rsplit("-", 1) if not name.endswith("nelder-mead") else (name[:-len("-nelder-mead")], "nelder-mead")
    if os.path.getsize(f) == 0:
        continue
    d = json.load(open(f))
    o = d["optimise"]
    # A feasible outcome: {"energy_j": …} (runs before schema 1 wrapped it as {"Ok": {…}}).
    energy = lambda e: e["outcome"].get("Ok", e["outcome"])["energy_j"]
    rows.setdefault(job, {})[search] = (energy(o["best"]), o["evals"], energy(o["best_grid"]),
                                        o["history_j"])
print("| example | best grid cell [J] | pattern [J] | its evaluations | argmin Nelder–Mead [J] | its evaluations "
      "| argmin after the pattern's evaluations [J] | argmin − pattern at equal evaluations |")
print("|---|---|---|---|---|---|---|---|")
for job, r in rows.items():
    if "pattern" in r and "nelder-mead" in r:
        (ep, np_, eg, _), (ea, na, _, h) = r["pattern"], r["nelder-mead"]
        # history_j[k]: the best energy after k evaluations (k = 0: the grid cell it starts from).
        at = h[min(np_, len(h) - 1)]
        print("| %s | %.2f | %.2f | %d | %.2f | %d | %.2f | %+.4f %% |" % (
            job, eg, ep, np_, ea, na, at, (at - ep) / ep * 100))
