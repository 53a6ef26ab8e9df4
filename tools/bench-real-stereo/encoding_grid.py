#!/usr/bin/env python3
"""Real-stereo verdicts per pair over a grid of stream encodings (README: encoding grid).

Runs stereoball-bench-real-stereo --in-process --json once per played size x JPEG quality x
chroma, keeps each run's JSON in OUT, and prints per pair how many runs scored it correct,
wrong and missed, with the misses' reasons; the sums per half of the set (odd pair numbers
tune, even ones report); each run's totals. A verdict that changes with the encoding depends
on one grey level of the image. --compare OLD prints the pairs whose verdict moved between
two such folders, run by run. Standard library only.
"""
import argparse
import collections
import json
import os
import re
import subprocess
import sys

SIZES = {"1152": ["--width-px", "1152"], "2304": ["--image-limit", "2304x1296"]}
STANDARD = ["--ball-diameter-m", "0.24", "--no-floor-check", "--snapshot-skew-ms", "16.7"]
VERDICTS = ("correct", "wrong", "missed")


def load_report(path):
    """A run's JSON report, or exit naming the file when it is not one (a run cut short)."""
    try:
        with open(path, encoding="utf-8") as f:
            report = json.load(f)
        keys = ("overall", "bands", "pairs")
        if not isinstance(report, dict) or any(k not in report for k in keys):
            raise ValueError("no overall, bands or pairs")
        return report
    except (OSError, ValueError) as e:
        sys.exit(f"{path}: not a stereoball-bench-real-stereo --json report ({e}); "
                 "delete it to run that cell again")


def run_name(size, quality, chroma):
    return f"{size}-q{quality}-{chroma}"


def run_grid(args):
    """Runs every grid cell whose JSON is not in args.out yet; returns {name: report}."""
    os.makedirs(args.out, exist_ok=True)
    bench = os.path.join(args.bin_dir, "stereoball-bench-real-stereo")
    runs = {}
    for size in args.sizes:
        for quality in args.qualities:
            for chroma in args.chromas:
                name = run_name(size, quality, chroma)
                path = os.path.join(args.out, name + ".json")
                if not os.path.exists(path):
                    cmd = [bench, *STANDARD, "--in-process", "--json", "--jpeg-quality", quality,
                           "--jpeg-chroma", chroma, *SIZES[size], *args.bench_args]
                    done = subprocess.run(cmd, capture_output=True, text=True, check=False)
                    if done.returncode != 0:
                        sys.exit(f"{name}: {' '.join(cmd)} exited {done.returncode}: "
                                 f"{done.stderr.strip()[-400:]}")
                    with open(path, "w", encoding="utf-8") as f:
                        f.write(done.stdout)
                runs[name] = load_report(path)
    return runs


def half_of(pair_id):
    """'tune' for odd pair numbers, 'report' for even ones (the set's README split)."""
    return "tune" if int(re.sub(r"\D", "", pair_id) or 0) % 2 else "report"


def reason_kind(pair):
    """A miss's reason with its numbers as #, or a wrong pair's why, shortened."""
    if pair["verdict"] == "wrong":
        return "WRONG " + re.sub(r"[-+]?\d+(\.\d+)?", "#", pair.get("why_wrong") or "")[:48]
    return re.sub(r"[-+]?\d+(\.\d+)?", "#", pair.get("reason") or "")[:64]


def print_table(runs, sizes):
    first = next(iter(runs.values()))
    sums = collections.Counter()
    print("pair  band       " + "  ".join(f"{s}: C/W/M of N  stable" for s in sizes))
    for p0 in first["pairs"]:
        pid = p0["pair"]
        cells, notes = [], []
        for size in sizes:
            counts, kinds = collections.Counter(), collections.Counter()
            for name, rep in runs.items():
                if not name.startswith(size + "-"):
                    continue
                p = next(x for x in rep["pairs"] if x["pair"] == pid)
                if p["verdict"] not in VERDICTS:
                    continue
                counts[p["verdict"]] += 1
                sums[(size, half_of(pid), p["verdict"])] += 1
                if p["verdict"] != "correct":
                    kinds[reason_kind(p)] += 1
            n = sum(counts.values())
            if n == 0:
                cells.append(f"{'excluded':>26}")
                continue
            stable = max(counts.values())
            cells.append(f"{counts['correct']:>3}/{counts['wrong']}/{counts['missed']} of {n}"
                         f"  {stable}/{n}".rjust(26))
            notes += [f"{size} {k} x{c}" for k, c in kinds.most_common(3)]
        print(f"{pid:>4}  {p0['band']:<10} " + "  ".join(cells))
        for note in notes:
            print(f"{'':18}{note}")
    print("\nper half (runs x pairs):")
    for size in sizes:
        for half in ("tune", "report"):
            c = [sums[(size, half, v)] for v in VERDICTS]
            print(f"  {size} {half:<6} correct {c[0]:>4}  wrong {c[1]:>3}  missed {c[2]:>4}")
    print("\nper run: overall correct/wrong/missed, |dy| <= 2 px band")
    for name, rep in sorted(runs.items()):
        o, b = rep["overall"], rep["bands"]["dy_le_2"]
        print(f"  {name:<14} {o['correct']:>3}/{o['wrong']}/{o['missed']:<3}"
              f"  {b['correct']}/{b['wrong']}/{b['missed']}")


def print_compare(old_runs, runs):
    print("verdicts that moved (old -> new):")
    moved = 0
    for name in sorted(runs):
        if name not in old_runs:
            continue
        old = {p["pair"]: p for p in old_runs[name]["pairs"]}
        for p in runs[name]["pairs"]:
            o = old.get(p["pair"])
            if o and o["verdict"] != p["verdict"]:
                moved += 1
                print(f"  {name:<14} pair {p['pair']:>4}: {o['verdict']} -> {p['verdict']}"
                      f"  ({reason_kind(p)})")
    print(f"  {moved} moved")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument("--bin-dir", default=os.path.join(here, "..", "..", "build", "bin"))
    ap.add_argument("--out", required=True, help="folder of the runs' JSON (reused if present)")
    ap.add_argument("--sizes", default="1152,2304", help="played sizes: 1152 and/or 2304")
    ap.add_argument("--qualities", default="85,90,95")
    ap.add_argument("--chromas", default="444,422,420")
    ap.add_argument("--compare", help="another --out folder: the verdicts that moved")
    ap.add_argument("bench_args", nargs="*", help="more flags for the bench (after --)")
    args = ap.parse_args()
    args.sizes = [s for s in args.sizes.split(",") if s]
    if any(s not in SIZES for s in args.sizes):
        sys.exit(f"--sizes: each of {sorted(SIZES)}")
    args.qualities = [q for q in args.qualities.split(",") if q]
    args.chromas = [c for c in args.chromas.split(",") if c]
    runs = run_grid(args)
    print_table(runs, args.sizes)
    if args.compare:
        old = {}
        for name in runs:
            path = os.path.join(args.compare, name + ".json")
            if os.path.exists(path):
                old[name] = load_report(path)
        print()
        print_compare(old, runs)


if __name__ == "__main__":
    main()
