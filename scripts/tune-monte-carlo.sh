#!/usr/bin/env bash
# Monte Carlo of `navsim tune` (docs/tuning.md): for each seed, a simulated
# USBL survey whose true sigmas are in its meta.toml; every sensor sigma and
# the IMU's two noise sigmas started 10x too large or 10x too small (a
# pattern drawn from the seed); tuned; replayed with the tuned meta.toml and
# with the true one. Prints one CSV row per seed and the summary. With
# CLOCK=1 the DVL's times are also written late by an offset drawn from the
# seed (-1.5 .. 1.5 s) and the four clocks are searched too (`--params`: the
# files have time columns of their own, whose clocks the default set
# trusts); the DVL's true offset is then minus that, the others' 0.
#
#   [CLOCK=1] scripts/tune-monte-carlo.sh [FIRST_SEED] [RUNS] [SCENARIO]
#
# Needs the release binary (`cargo build --release`) and python3.
set -euo pipefail
first=${1:-5000}
runs=${2:-100}
scenario=${3:-lawnmower-usbl}
root="$(cd "$(dirname "$0")/.." && pwd)"
navsim="$root/target/release/navsim"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
rows="$work/rows.jsonl"
for ((seed = first; seed < first + runs; seed++)); do
    log="$work/log"
    rm -rf "$log"
    "$navsim" simulate "$scenario" --seed "$seed" --out "$log" >/dev/null
    cp "$log/meta.toml" "$work/true.toml"
    true_json="$("$navsim" replay "$log" --model sdins25 --json 2>/dev/null)"
    late=0
    if [[ "${CLOCK:-0}" == 1 ]]; then
        late=$(python3 -c "import sys; print(((int(sys.argv[1]) * 7919) % 301 - 150) / 100)" "$seed")
        python3 - "$log/dvl.csv" "$late" <<'EOF'
import sys
path, late = sys.argv[1], float(sys.argv[2])
lines = open(path).read().splitlines()
out = [lines[0]]
for line in lines[1:]:
    t, rest = line.split(",", 1)
    out.append(f"{float(t) + late!r},{rest}")
open(path, "w").write("\n".join(out) + "\n")
EOF
    fi
    python3 - "$log/meta.toml" "$seed" <<'EOF'
import re, sys
path, seed = sys.argv[1], int(sys.argv[2])
text = open(path).read()
keys = ["dvl", "depth", "heading", "usbl"]
out, section = [], None
for line in text.splitlines():
    m = re.match(r"\s*\[(.*)\]", line)
    if m:
        section = m.group(1).strip()
    k = line.split("=")[0].strip()
    bit = None
    if section and section.startswith("sensors.") and k == "noise_sigma":
        bit = keys.index(section[8:])
    if section == "sensors.imu" and k in ("gyro_noise_sigma", "accel_noise_sigma"):
        bit = 4
    if bit is not None:
        v = float(line.split("=")[1])
        factor = 10.0 if (seed >> bit) & 1 else 0.1
        line = f"{k} = {v * factor!r}"
    out.append(line)
open(path, "w").write("\n".join(out) + "\n")
EOF
    params=()
    if [[ "${CLOCK:-0}" == 1 ]]; then
        list=sensors.dvl.noise_sigma,sensors.depth.noise_sigma,sensors.heading.noise_sigma,sensors.usbl.noise_sigma
        list=$list,sensors.imu.gyro_noise_sigma,sensors.imu.accel_noise_sigma
        list=$list,files.dvl.time.offset_s,files.depth.time.offset_s,files.heading.time.offset_s,files.usbl.time.offset_s
        params=(--params "$list")
    fi
    if ! tune_json="$("$navsim" tune "$log" --model sdins25 "${params[@]}" --json --write "$work/tuned.toml" 2>"$work/tune.err")"; then
        echo "{\"seed\": $seed, \"failed\": $(python3 -c 'import json,sys; print(json.dumps(open(sys.argv[1]).read().strip()))' "$work/tune.err")}" >>"$rows"
        echo "seed $seed: tune failed" >&2
        continue
    fi
    cp "$work/tuned.toml" "$log/meta.toml"
    tuned_json="$("$navsim" replay "$log" --model sdins25 --json 2>/dev/null)"
    python3 - "$seed" "$work/true.toml" "$late" <<EOF >>"$rows"
import json, sys, tomllib
seed = int(sys.argv[1])
late = float(sys.argv[3])
true = tomllib.load(open(sys.argv[2], "rb"))["sensors"]
t = json.loads('''$tune_json''')
a = json.loads('''$true_json''')
b = json.loads('''$tuned_json''')
ratios = {}
clocks = {}
for k, p in t["parameters"].items():
    if k.startswith("files."):
        truth = -late if k == "files.dvl.time.offset_s" else 0.0
        clocks[k] = {"error": p["value"] - truth, "identifiable": p["identifiable"]}
        continue
    _, s, name = k.split(".")
    ratios[k] = {"ratio": p["value"] / true[s][name], "identifiable": p["identifiable"]}
print(json.dumps({"seed": seed, "replays": t["replays"], "converged": t["converged"],
    "ratios": ratios, "clocks": clocks, "late": late,
    "rms_true": a["horizontal_error_rms_m"], "rms_tuned": b["horizontal_error_rms_m"],
    "nees_true": a["nees_mean"], "nees_tuned": b["nees_mean"]}))
EOF
    echo "seed $seed done" >&2
done
python3 - "$rows" "$root/scripts" <<'EOF'
import statistics, sys
sys.path.insert(0, sys.argv[2])
from monte_carlo_rows import pct, read
rows = read(sys.argv[1])
n = len(rows)
print(f"replays per tuning: median {statistics.median(r['replays'] for r in rows)}, max {max(r['replays'] for r in rows)}; converged {sum(r['converged'] for r in rows)}/{n}")
for k in rows[0]["ratios"]:
    ident = [r["ratios"][k]["ratio"] for r in rows if r["ratios"][k]["identifiable"]]
    within = sum(abs(x - 1) <= 0.25 for x in ident)
    line = f"{k}: identified in {len(ident)}/{n}"
    if ident:
        err = [abs(x - 1) for x in ident]
        line += f", within 25 % in {within}/{len(ident)}, |tuned/true - 1| median {statistics.median(err):.3f} p95 {pct(err, 0.95):.3f} max {max(err):.3f}"
    print(line)
for k in rows[0].get("clocks", {}):
    found = [r for r in rows if r["clocks"][k]["identifiable"]]
    err = [abs(r["clocks"][k]["error"]) for r in found]
    kept = [abs(r["clocks"][k]["error"]) for r in rows if not r["clocks"][k]["identifiable"]]
    line = f"{k}: identified in {len(found)}/{n}"
    if err:
        line += f", |found - true| median {statistics.median(err):.3f} s p95 {pct(err, 0.95):.3f} s max {max(err):.3f} s"
    if kept:
        line += f"; kept at the given value in {len(kept)} (|given - true| max {max(kept):.3f} s)"
    print(line)
ratio = [r["rms_tuned"] / r["rms_true"] for r in rows]
print(f"horizontal RMS tuned / true sigmas: median {statistics.median(ratio):.3f} p95 {pct(ratio, 0.95):.3f} max {max(ratio):.3f}; within 10 % in {sum(x <= 1.1 for x in ratio)}/{n}")
print(f"median horizontal RMS: true sigmas {statistics.median(r['rms_true'] for r in rows):.3f} m, tuned {statistics.median(r['rms_tuned'] for r in rows):.3f} m")
print(f"mean NEES (9 states): true sigmas {statistics.mean(r['nees_true'] for r in rows):.2f}, tuned {statistics.mean(r['nees_tuned'] for r in rows):.2f}")
EOF
