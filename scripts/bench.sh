#!/usr/bin/env bash
# Runs the criterion benchmarks and prints every result as a ratio against the
# baseline measured in the same run (medians of criterion's samples).
#
#   scripts/bench.sh                 # all benches (the scenario bench takes ~10 min)
#   scripts/bench.sh --quick         # shorter measurement, 20-run Monte Carlo
#   scripts/bench.sh propagation update   # only these benches
#   scripts/bench.sh --report        # print the ratios of the last results only
#   scripts/bench.sh --callgrind     # instructions per propagation and update (needs
#                                    # valgrind); fails if one is >10 % above
#                                    # models/perf/instructions.toml
#   scripts/bench.sh --callgrind --update-baseline   # rewrite that file
#   scripts/bench.sh --expansion     # compile time of the model declarations
#
# Benches: propagation, update, filter_step, replay_step, replay_pipeline, scenario
# (crate models) and strapdown (crate nav-runtime). Needs python3 to read criterion's JSON.
# See the README section "Performance" for what each ratio means and the targets.
set -euo pipefail

cd "$(dirname "$0")/.."

quick=0
report_only=0
update_baseline=0
mode=bench
benches=()
for arg in "$@"; do
    case "$arg" in
        --quick) quick=1 ;;
        --report) report_only=1 ;;
        --callgrind) mode=callgrind ;;
        --update-baseline) update_baseline=1 ;;
        --expansion) mode=expansion ;;
        -h | --help)
            sed -n '2,18p' "$0"
            exit 0
            ;;
        propagation | update | filter_step | replay_step | replay_pipeline | scenario | strapdown) benches+=("$arg") ;;
        *)
            echo "unknown argument: $arg (see --help)" >&2
            exit 2
            ;;
    esac
done
if [ ${#benches[@]} -eq 0 ]; then
    benches=(propagation update filter_step replay_step replay_pipeline strapdown scenario)
fi

target_dir=$(cargo metadata --no-deps --format-version 1 |
    python3 -c 'import json, sys; print(json.load(sys.stdin)["target_directory"])')

# Instructions per call of each propagation variant: the propagation bench
# binary in its PROPAGATE_ONLY mode under callgrind, collecting only inside
# the variant's function (and its callees), 1000 calls.
if [ "$mode" = callgrind ]; then
    command -v valgrind >/dev/null || {
        echo "valgrind not found" >&2
        exit 1
    }
    executable() { # bench name
        cargo bench -p models --bench "$1" --no-run 2>&1 | tail -1 >&2
        cargo bench -p models --bench "$1" --no-run --message-format=json 2>/dev/null |
            python3 -c 'import json, sys
for line in sys.stdin:
    m = json.loads(line)
    if m.get("reason") == "compiler-artifact" and m["target"]["name"] == sys.argv[1] and m.get("executable"):
        print(m["executable"])' "$1"
    }
    propagation_bin=$(executable propagation)
    update_bin=$(executable update)
    calls=1000
    count() { # ONLY-variable value function-pattern binary
        env "$1=$2" PROPAGATE_CALLS=$calls UPDATE_CALLS=$calls valgrind --tool=callgrind \
            --callgrind-out-file=/dev/null --toggle-collect="$3" "$4" 2>&1 |
            awk -v c=$calls '/Collected/ { v = $4 / c; if (v > m) m = v } END { printf "%.0f", m }'
    }
    measured=$(mktemp)
    trap 'rm -f "$measured"' EXIT
    printf "%-10s %12s %12s %12s %18s %14s\n" model generated dense hand-written "dense incl. F, Qd" generated/dense
    for m in sdins25 leveling6 marker9 px4_ekf24; do
        g=$(count PROPAGATE_ONLY "$m/generated" '*generated_propagate*' "$propagation_bin")
        d=$(count PROPAGATE_ONLY "$m/dense" '*dense_propagate*' "$propagation_bin")
        dm=$(count PROPAGATE_ONLY "$m/dense_with_model" '*dense_propagate_with_model*' "$propagation_bin")
        h=-
        [ "$m" = sdins25 ] && h=$(count PROPAGATE_ONLY "$m/handwritten" '*HandWrittenSdins25*propagate*' "$propagation_bin")
        printf "%-10s %12s %12s %12s %18s %14.3f\n" "$m" "$g" "$d" "$h" "$dm" "$(echo "$g / $d" | bc -l)"
        echo "propagate.$m = $g" >>"$measured"
    done
    # SDINS-25 composed, generated in f64 and in f32 (`scalar f32;`).
    p64=$(count PROPAGATE_ONLY sdins25_precision/generated_f64 '*propagate_f64*' "$propagation_bin")
    p32=$(count PROPAGATE_ONLY sdins25_precision/generated_f32 '*propagate_f32*' "$propagation_bin")
    printf "\n%-20s %12s %12s %14s\n" "SDINS-25 precision" f64 f32 f32/f64
    printf "%-20s %12s %12s %14.3f\n" propagation "$p64" "$p32" "$(echo "$p32 / $p64" | bc -l)"
    echo "propagate.sdins25_f32 = $p32" >>"$measured"
    # PX4's 24-state model in both precisions.
    x64=$(count PROPAGATE_ONLY px4_ekf24_precision/generated_f64 '*px4_propagate_f64*' "$propagation_bin")
    x32=$(count PROPAGATE_ONLY px4_ekf24_precision/generated_f32 '*px4_propagate_f32*' "$propagation_bin")
    printf "%-20s %12s %12s %14.3f\n" "PX4 24-state" "$x64" "$x32" "$(echo "$x32 / $x64" | bc -l)"
    echo "propagate.px4_ekf24_f32 = $x32" >>"$measured"
    # The same model declared in the bench crate with the rotation written as
    # a matrix (textbook and homogeneous forms), against the builtin's.
    builtin=$(awk -F' = ' '$1 == "propagate.px4_ekf24" { print $2 }' "$measured")
    printf "\n%-20s %12s %12s %14s\n" "PX4 rotation as" instructions quat_to_dcm ratio
    for m in rotation_matrix homogeneous_matrix; do
        r=$(count PROPAGATE_ONLY "px4_$m/generated" '*generated_propagate*' "$propagation_bin")
        printf "%-20s %12s %12s %14.3f\n" "$m" "$r" "$builtin" "$(echo "$r / $builtin" | bc -l)"
        echo "propagate.px4_$m = $r" >>"$measured"
    done
    printf "\n%-20s %12s %12s %14s\n" "update (SDINS-25)" generated dense generated/dense
    for s in dvl compass usbl depth; do
        g=$(count UPDATE_ONLY "$s/generated" '*generated_update*' "$update_bin")
        d=$(count UPDATE_ONLY "$s/dense" '*dense_joseph_update*' "$update_bin")
        printf "%-20s %12s %12s %14.3f\n" "$s" "$g" "$d" "$(echo "$g / $d" | bc -l)"
        echo "update.$s = $g" >>"$measured"
    done
    # The SDINS-25 log replay per IMU sample (scheduler, strapdown,
    # error-state filter, aiding updates), against one generated propagation.
    replay_bin=$(executable replay_step)
    replay_out=$(REPLAY_ONLY=1 valgrind --tool=callgrind --callgrind-out-file=/dev/null \
        --toggle-collect='*run_vehicle*' "$replay_bin" 2>&1)
    # One `Collected` line per thread: their sum.
    replay_instr=$(echo "$replay_out" | awk '/Collected/ { s += $4 } END { print s }')
    replay_samples=$(echo "$replay_out" | awk '/^samples/ { print $2 }')
    replay=$((replay_instr / replay_samples))
    propagate=$(awk -F' = ' '$1 == "propagate.sdins25" { print $2 }' "$measured")
    printf "\n%-20s %12s %12s %14s\n" "replay (SDINS-25)" per-sample propagation ratio
    printf "%-20s %12s %12s %14.2f\n" "$replay_samples samples" "$replay" "$propagate" \
        "$(echo "$replay / $propagate" | bc -l)"
    echo "replay.sdins25 = $replay" >>"$measured"
    # Regression check against the checked-in instruction counts: more than
    # 10 % above the baseline fails (exit 1). `--update-baseline` rewrites it.
    baseline=models/perf/instructions.toml
    if [ "$update_baseline" -eq 1 ]; then
        {
            echo "# Instructions per call (callgrind, 1000 calls) of the generated code,"
            echo "# checked by 'scripts/bench.sh --callgrind' (fails above +10 %)."
            echo "# Rewrite with 'scripts/bench.sh --callgrind --update-baseline'."
            cat "$measured"
        } >"$baseline"
        echo "wrote $baseline"
        exit 0
    fi
    python3 - "$baseline" "$measured" <<'PY'
import sys
def read(path):
    out = {}
    for line in open(path):
        line = line.split("#")[0].strip()
        if line:
            k, v = line.split("=")
            out[k.strip()] = int(v)
    return out
base, now = read(sys.argv[1]), read(sys.argv[2])
failed = False
print()
for k in sorted(now):
    if k not in base:
        print(f"{k}: {now[k]} (no baseline)")
        continue
    change = now[k] / base[k] - 1
    bad = change > 0.10
    failed |= bad
    print(f"{k:<22} {now[k]:>8} vs baseline {base[k]:>8} ({change:+.1%}){'  REGRESSION > 10 %' if bad else ''}")
sys.exit(1 if failed else 0)
PY
    exit $?
fi

# Compile time of the model declarations: a throw-away crate holding only the
# declarations of models/src/*/model.rs (behind a feature) on nav-runtime
# without std, built with and without them after touching its lib.rs; the
# difference is the expansion plus the compilation of the generated code
# (`check`: expansion + type checking; `build --release`: + optimized codegen).
# Medians of 3.
if [ "$mode" = expansion ]; then
    probe=$(mktemp -d)
    trap 'rm -rf "$probe"' EXIT
    mkdir -p "$probe/src"
    cat >"$probe/Cargo.toml" <<TOML
[package]
name = "expand_probe"
version = "0.0.0"
edition = "2021"
publish = false

[dependencies]
nav-runtime = { path = "$PWD/nav-runtime", default-features = false }

[features]
models = []

[workspace]
TOML
    cp Cargo.lock "$probe/"
    {
        echo '#![no_std]'
        for f in "$PWD"/models/src/*/model.rs; do
            m=$(basename "$(dirname "$f")")
            echo "#[cfg(feature = \"models\")] #[path = \"$f\"] pub mod $m;"
        done
    } >"$probe/src/lib.rs"
    echo "declarations: $(ls models/src/*/model.rs | tr '\n' ' ')"
    export CARGO_TARGET_DIR="$probe/target"
    time_of() { # cargo args...; median of 3 rebuilds of the probe crate only
        for _ in 1 2 3; do
            touch "$probe/src/lib.rs"
            s=$(date +%s.%N)
            (cd "$probe" && cargo "$@" -q 2>/dev/null)
            e=$(date +%s.%N)
            echo "$e - $s" | bc -l
        done | sort -n | sed -n 2p
    }
    for cmd in "check" "build" "build --release"; do
        # shellcheck disable=SC2086
        (cd "$probe" && cargo $cmd -q --features models 2>/dev/null && cargo $cmd -q 2>/dev/null)
        # shellcheck disable=SC2086
        without=$(time_of $cmd)
        # shellcheck disable=SC2086
        with=$(time_of $cmd --features models)
        printf "cargo %-16s without %6.2f s  with %6.2f s  declarations cost %6.2f s\n" \
            "$cmd" "$without" "$with" "$(echo "$with - $without" | bc -l)"
    done
    echo "load average $(cut -d' ' -f1-3 /proc/loadavg) on $(nproc) cores"
    exit 0
fi

if [ "$report_only" -eq 0 ]; then
    criterion_args=()
    if [ "$quick" -eq 1 ]; then
        criterion_args=(--warm-up-time 1 --measurement-time 2)
        export BENCH_MC_RUNS="${BENCH_MC_RUNS:-20}"
    fi
    echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
    for b in "${benches[@]}"; do
        crate=models
        [ "$b" = strapdown ] && crate=nav-runtime
        echo "== cargo bench -p $crate --bench $b"
        # Criterion's own per-benchmark lines go to the log; the ratios follow below.
        cargo bench -p "$crate" --bench "$b" -- "${criterion_args[@]}" 2>&1 |
            grep -E '^[a-z].*/|time:' || {
            echo "bench $b failed" >&2
            exit 1
        }
    done
    echo "machine after: load average $(cut -d' ' -f1-3 /proc/loadavg)"
fi

python3 - "$target_dir/criterion" <<'EOF'
import json, os, sys

root = sys.argv[1]
med = {}
mc = {}  # threads -> (mtime, runs, median) of the newest Monte Carlo result
for dirpath, _, files in os.walk(root):
    if os.path.basename(dirpath) == "new" and "estimates.json" in files:
        with open(os.path.join(dirpath, "benchmark.json")) as f:
            b = json.load(f)
        with open(os.path.join(dirpath, "estimates.json")) as f:
            m = json.load(f)["median"]["point_estimate"]  # ns
        med[b["full_id"]] = m
        if b["group_id"] == "montecarlo/lawnmower-dvl" and b.get("value_str"):
            t = b["function_id"]
            mtime = os.path.getmtime(os.path.join(dirpath, "estimates.json"))
            if t not in mc or mc[t][0] < mtime:
                mc[t] = (mtime, b["value_str"], m)

def t(ns):
    for unit, scale in (("s", 1e9), ("ms", 1e6), ("us", 1e3)):
        if ns >= scale:
            return f"{ns / scale:8.3f} {unit}"
    return f"{ns:8.1f} ns"

def ratio(label, num, den, target=None, higher_is_better=False):
    if num not in med or den not in med:
        return
    r = med[num] / med[den]
    verdict = ""
    if target is not None:
        ok = r >= target if higher_is_better else r <= target
        verdict = f"  target {'>=' if higher_is_better else '<='} {target}: {'met' if ok else 'NOT met'}"
    print(f"  {label:<58} {t(med[num])} / {t(med[den])} = {r:7.3f}{verdict}")

print("\nRatios (medians; numerator / baseline of the same run)")
print("Covariance propagation P <- Phi P Phi^T + Qd")
for m in ("sdins25", "leveling6", "marker9"):
    g = f"propagate/{m}"
    target = 0.13 if m == "sdins25" else None
    ratio(f"{m}: generated / dense", f"{g}/generated", f"{g}/dense", target)
    ratio(f"{m}: generated / dense incl. F, Qd eval", f"{g}/generated", f"{g}/dense_with_model")
    ratio(f"{m}: hand-written / dense", f"{g}/handwritten", f"{g}/dense")
    ratio(f"{m}: generated / hand-written", f"{g}/generated", f"{g}/handwritten", 1.0)

print("Measurement update (Ekf::update vs dense Joseph)")
for s in ("dvl", "compass", "compass_small_angle", "usbl", "depth"):
    target = 0.2 if s == "dvl" else None
    ratio(f"{s}: Ekf::update / dense Joseph", f"update/{s}/generated", f"update/{s}/dense", target)
    ratio(f"{s}: innovation_terms / dense PH^T, HPH^T", f"innovation_terms/{s}/generated", f"innovation_terms/{s}/dense")

print("Full SDINS-25 step at 100 Hz (aiding at 2 Hz amortized)")
g = "step/sdins25"
if f"{g}/full_step_x50" in med:
    med[f"{g}/full_step"] = med[f"{g}/full_step_x50"] / 50
    med[f"{g}/aiding_per_step"] = med[f"{g}/aiding_burst"] / 50 if f"{g}/aiding_burst" in med else 0
    ratio("full step / one dense propagation", f"{g}/full_step", f"{g}/dense_propagation", 1.0)
    for part in ("strapdown", "predict", "aiding_per_step"):
        ratio(f"  part: {part} / full step", f"{g}/{part}", f"{g}/full_step")
for fn in ("update_rates", "update_increments", "mechanization_rates"):
    if f"strapdown/{fn}" in med:
        print(f"  strapdown::{fn:<40} {t(med[f'strapdown/{fn}'])}")

print("SDINS-25 log replay per IMU sample (60 s of lawnmower-dvl)")
ratio("replay per sample / one generated propagation", "replay/sdins25/replay_per_sample", "replay/sdins25/propagate_covariance", 1.5)
ratio("navsim replay: streamed, preflight alongside / loaded, then checked", "replay/pipeline/streamed_alongside", "replay/pipeline/loaded_then_checked", 1.0)
for motion in ("moving", "stationary"):
    g = f"replay/leveling6-{motion}"
    ratio(f"leveling6 ({motion}): streamed / loaded, then checked", f"{g}/streamed_alongside", f"{g}/loaded_then_checked")

print("Scenario runs (lawnmower-dvl, 500 s of data)")
g = "scenario/lawnmower-dvl"
for fn, label in (("run_one", "simulate + filter + score"), ("filter_only", "filter only")):
    if f"{g}/{fn}" in med:
        rtf = 500e9 / med[f"{g}/{fn}"]
        verdict = f"  target >= 5000: {'met' if rtf >= 5000 else 'NOT met'}" if fn == "run_one" else ""
        print(f"  real-time factor, {label:<26} 500 s / {t(med[f'{g}/{fn}'])} = {rtf:9.0f}{verdict}")
if f"{g}/run_one" in med and f"{g}/reference" in med:
    first = med[f"{g}/run_one"] + med[f"{g}/reference"]
    print(f"  real-time factor, first run of a process (+ shared truth {t(med[f'{g}/reference'])}) = {500e9 / first:9.0f}")
if "threads_1" in mc and "threads_2" in mc:
    med["mc1"], med["mc2"] = mc["threads_1"][2], mc["threads_2"][2]
    print(f"  Monte Carlo ({mc['threads_1'][1]} and {mc['threads_2'][1]} runs): 1 thread {t(med['mc1'])}, 2 threads {t(med['mc2'])}")
    ratio("Monte Carlo speed-up, 1 thread / 2 threads", "mc1", "mc2", 1.8, higher_is_better=True)
EOF
