#!/usr/bin/env bash
# Monte Carlo of the clock search of `navsim tune` (docs/tuning.md, "Clock
# offsets"): for each seed, the survey of `models::sdins25::clock_survey`
# (the lawn-mowing survey with speed changes, a 0.01 m/s bottom-track DVL at
# 1 Hz, depth meter, compass) with the DVL stamped late by an offset drawn
# from the seed (-1.5 .. 1.5 s); replayed as given (no clock offset), tuned,
# replayed with the tuned meta.toml and with the true offset. Prints the
# summary.
#
#   scripts/clock-monte-carlo.sh [FIRST_SEED] [RUNS]
#
# Builds the release binary and the example that writes the log; needs python3.
set -euo pipefail
first=${1:-7000}
runs=${2:-100}
root="$(cd "$(dirname "$0")/.." && pwd)"
navsim="$root/target/release/navsim"
survey="$root/target/release/examples/clock_survey"
(cd "$root" && cargo build --release -q -p navsim && cargo build --release -q -p models --example clock_survey)
work="$(mktemp -d)"
trap '[[ -n "${KEEP:-}" ]] || rm -rf "$work"' EXIT
rows="$work/rows.jsonl"
rms() { "$navsim" replay "$1" --model sdins20 --json 2>/dev/null |
    python3 -c 'import json,sys; print(json.load(sys.stdin)["horizontal_error_rms_m"])'; }
for ((seed = first; seed < first + runs; seed++)); do
    log="$work/log"
    rm -rf "$log"
    late=$(python3 -c "import sys; print(((int(sys.argv[1]) * 7919) % 301 - 150) / 100)" "$seed")
    "$survey" "$seed" "$late" "$log"
    cp "$log/meta.toml" "$work/given.toml"
    rms_given=$(rms "$log")
    printf '\n[files.dvl]\ntime = { offset_s = %s }\n' "$(python3 -c "print(-$late)")" >>"$log/meta.toml"
    rms_true=$(rms "$log")
    cp "$work/given.toml" "$log/meta.toml"
    # The default set, and the DVL's clock (its file has a time column of
    # its own, so the clock is searched only when asked for).
    params=sensors.dvl.noise_sigma,sensors.depth.noise_sigma,sensors.heading.noise_sigma
    params=$params,sensors.imu.gyro_noise_sigma,sensors.imu.accel_noise_sigma,files.dvl.time.offset_s
    if ! tune_json="$("$navsim" tune "$log" --model sdins20 --params "$params" --json --write "$work/tuned.toml" 2>"$work/tune.err")"; then
        echo "{\"seed\": $seed, \"failed\": $(python3 -c 'import json,sys; print(json.dumps(open(sys.argv[1]).read().strip()))' "$work/tune.err")}" >>"$rows"
        echo "seed $seed: tune failed" >&2
        continue
    fi
    cp "$work/tuned.toml" "$log/meta.toml"
    rms_tuned=$(rms "$log")
    python3 - "$seed" "$late" "$rms_given" "$rms_true" "$rms_tuned" <<EOF >>"$rows"
import json, sys
seed, late, given, true, tuned = int(sys.argv[1]), *map(float, sys.argv[2:])
p = json.loads('''$tune_json''')["parameters"]["files.dvl.time.offset_s"]
print(json.dumps({"seed": seed, "late": late, "found": p["value"], "identifiable": p["identifiable"],
    "standard_error_s": p["standard_error_s"], "reason": p["reason"],
    "rms_given": given, "rms_true_clock": true, "rms_tuned": tuned}))
EOF
    echo "seed $seed done" >&2
done
python3 - "$rows" "$root/scripts" <<'EOF'
import statistics, sys
sys.path.insert(0, sys.argv[2])
from monte_carlo_rows import pct, read
rows = read(sys.argv[1])
n = len(rows)
found = [r for r in rows if r["identifiable"]]
err = [abs(r["found"] + r["late"]) for r in found]
print(f"DVL clock found in {len(found)}/{n}; |found - true| median {statistics.median(err):.3f} s, p95 {pct(err, 0.95):.3f} s, max {max(err):.3f} s; within 0.1 s in {sum(e <= 0.1 for e in err)}")
kept = [r for r in rows if not r["identifiable"]]
for r in kept:
    print(f"  seed {r['seed']}: late {r['late']} s, kept: {r['reason']}")
small = [r for r in kept if abs(r["late"]) < 0.3]
print(f"  kept with |true offset| < 0.3 s: {len(small)} of {len(kept)}")
for key in ("rms_given", "rms_true_clock", "rms_tuned"):
    print(f"median horizontal RMS {key}: {statistics.median(r[key] for r in rows):.3f} m")
ratio = [r["rms_tuned"] / r["rms_true_clock"] for r in rows]
print(f"RMS tuned / with the true clock and given sigmas: median {statistics.median(ratio):.3f}, p95 {pct(ratio, 0.95):.3f}, max {max(ratio):.3f}")
EOF
