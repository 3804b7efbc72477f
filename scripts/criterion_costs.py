#!/usr/bin/env python3
"""Turn criterion's results into the cost column of `hsv-run trade`.

Reads every target/criterion/**/new/benchmark.json + estimates.json (written by
`cargo bench -p hsv-benches ...`) and writes a CSV `model,seconds,bench`: for each model, the
mean time of one evaluation from the first benchmark (sorted by id) whose function id starts with
the model's name, among the per-model families (groups aero/, heat-flux/, conduction/,
propulsion/, structures/; whole jobs, flutter, STL and the plugin-boundary groups are left out). Pass it to
`hsv-run trade --costs FILE` (or `costs = "FILE"` in `[trade]`): a case's cost is then the sum of
its varied models' seconds.

    python3 scripts/criterion_costs.py                      # -> costs.csv
    python3 scripts/criterion_costs.py --out my-costs.csv --criterion target/criterion
    python3 scripts/criterion_costs.py --markdown           # every bench as a Markdown table
"""

import argparse
import csv
import json
import sys
from pathlib import Path

# Groups whose benchmarks time one model each, named by the first part of the function id.
PER_MODEL = ("aero/", "heat-flux/", "conduction/", "propulsion/", "structures/")


def read_benches(root: Path):
    """(group, function, full id, mean s, std-dev s) of every benchmark under `root`."""
    rows = []
    for estimates in sorted(root.glob("**/new/estimates.json")):
        meta_path = estimates.with_name("benchmark.json")
        if not meta_path.exists():
            continue
        meta = json.loads(meta_path.read_text())
        est = json.loads(estimates.read_text())
        # Criterion reports nanoseconds.
        mean_s = est["mean"]["point_estimate"] * 1e-9
        std_s = est["std_dev"]["point_estimate"] * 1e-9
        rows.append(
            (
                meta.get("group_id", ""),
                meta.get("function_id") or "",
                meta.get("full_id", ""),
                mean_s,
                std_s,
            )
        )
    rows.sort(key=lambda r: r[2])
    return rows


def model_costs(rows):
    """model -> (seconds, bench id): the first per-model benchmark of each model name."""
    costs = {}
    for group, function, full_id, mean_s, _ in rows:
        if not group.startswith(PER_MODEL) or not function:
            continue
        model = function.split("/")[0].strip()
        if not model or " " in model or model in costs:
            continue
        costs[model] = (mean_s, full_id)
    return costs


def human(seconds: float) -> str:
    for unit, scale in (("s", 1.0), ("ms", 1e-3), ("µs", 1e-6)):
        if seconds >= scale:
            return f"{seconds / scale:.3g} {unit}"
    return f"{seconds / 1e-9:.3g} ns"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--criterion", default="target/criterion", type=Path,
                        help="criterion output folder (default: target/criterion)")
    parser.add_argument("--out", default="costs.csv", type=Path,
                        help="cost CSV to write (default: costs.csv)")
    parser.add_argument("--markdown", action="store_true",
                        help="print every benchmark as a Markdown table instead")
    args = parser.parse_args()
    if not args.criterion.is_dir():
        print(f"error: no criterion output in {args.criterion}; run `cargo bench -p hsv-benches` "
              "first", file=sys.stderr)
        return 1
    rows = read_benches(args.criterion)
    if not rows:
        print(f"error: no new/estimates.json under {args.criterion}", file=sys.stderr)
        return 1
    if args.markdown:
        print("| benchmark | mean | std. dev. |")
        print("|---|---:|---:|")
        for _, _, full_id, mean_s, std_s in rows:
            print(f"| {full_id} | {human(mean_s)} | {human(std_s)} |")
        return 0
    costs = model_costs(rows)
    with args.out.open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(["model", "seconds", "bench"])
        for model in sorted(costs):
            seconds, bench = costs[model]
            writer.writerow([model, f"{seconds:.6e}", bench])
    print(f"wrote {args.out}: {len(costs)} models from {len(rows)} benchmarks")
    return 0


if __name__ == "__main__":
    sys.exit(main())
