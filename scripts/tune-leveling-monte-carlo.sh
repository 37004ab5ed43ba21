#!/usr/bin/env bash
# Monte Carlo of `navsim tune --model leveling6` (docs/tuning.md): for each
# seed, a simulated S-track (`leveling-moving`, speed log with 0.1 m/s of
# noise, the sigma its meta.toml gives, and 0.1 m/s of constant bias, which
# the velocity estimate absorbs); the speed log's noise sigma started 10x
# too large (even seeds) or 10x too small (odd); tuned. Prints one row per
# seed (seed, start, tuned, identified, standard error of ln sigma,
# replays, converged) and the summary.
#
#   scripts/tune-leveling-monte-carlo.sh [FIRST_SEED] [RUNS]
#
# Needs the release binary (`cargo build --release`) and python3.
set -euo pipefail
first=${1:-9000}
runs=${2:-100}
root="$(cd "$(dirname "$0")/.." && pwd)"
navsim="$root/target/release/navsim"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
for ((seed = first; seed < first + runs; seed++)); do
    log="$work/log"
    rm -rf "$log"
    "$navsim" simulate leveling-moving --seed "$seed" --out "$log" >/dev/null
    start=$([[ $((seed % 2)) == 0 ]] && echo 1.0 || echo 0.01)
    sed -i "/\[sensors.speed\]/,/^$/ s/^noise_sigma = .*/noise_sigma = $start/" "$log/meta.toml"
    "$navsim" tune "$log" --model leveling6 --json 2>/dev/null | python3 -c "
import json, sys
d = json.load(sys.stdin)
p = d['parameters']['sensors.speed.noise_sigma']
print($seed, $start, p['value'], p['identifiable'], p['log_standard_error'], d['replays'], d['converged'])"
done | tee "$work/rows.txt"
python3 - "$work/rows.txt" <<'PY'
import math, sys
rows = [l.split() for l in open(sys.argv[1])]
true = 0.1
value = [float(r[2]) for r in rows]
se = [float(r[4]) for r in rows]
err = sorted(abs(v / true - 1) for v in value)
z = [math.log(v / true) / s for v, s in zip(value, se)]
replays = sorted(int(r[5]) for r in rows)
n = len(rows)
print(f"runs {n}: identified {sum(r[3] == 'True' for r in rows)}, converged "
      f"{sum(r[6] == 'True' for r in rows)}, within 25 % {sum(e < 0.25 for e in err)}")
print(f"|tuned/true - 1| median {err[n // 2]:.3f}, p95 {err[int(0.95 * n) - 1]:.3f}, max {err[-1]:.3f}")
print(f"within 1.96 standard errors {sum(abs(q) < 1.96 for q in z)}, RMS error/SE "
      f"{math.sqrt(sum(q * q for q in z) / n):.2f}")
print(f"replays median {replays[n // 2]}, max {replays[-1]}")
PY
