"""The rows of a Monte Carlo script (one JSON object per seed, a failed
tuning as {"seed", "failed"}): read, failures listed, and percentiles."""
import json


def read(path):
    """The rows of tunings that did not fail, after printing those that did."""
    rows = [json.loads(line) for line in open(path)]
    failed = [r for r in rows if r.get("failed")]
    for r in failed:
        print(f"seed {r['seed']}: tune failed: {r['failed']}")
    print(f"tunings failed: {len(failed)} of {len(rows)}")
    rows = [r for r in rows if not r.get("failed")]
    print(f"runs {len(rows)}, seeds {rows[0]['seed']}..{rows[-1]['seed']}")
    return rows


def pct(xs, q):
    """The q quantile of xs (the value at index floor(q n))."""
    xs = sorted(xs)
    return xs[min(len(xs) - 1, int(q * len(xs)))]
