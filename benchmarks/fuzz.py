"""Mutation fuzzing of every file tactilecal reads (issue 11): no traceback, no silent nonsense.

Seed files are the real exports of ``../shared/realdata`` (cut to their first frames, so a
mutation reads in milliseconds) when present, plus files that tactilecal itself writes: an
I-Scan movie, a dead-weight manifest with its recordings, a load-cell CSV, and calibration,
equilibration and FILTER.json files. Each mutation (byte flips, truncation, lines deleted or
repeated, a lone CR, an extra comma, re-encoding, hostile header values and cells, JSON keys
deleted or given hostile values) is opened with the matching public reader, and classed:

- ``ok``: read, and every value is inside what the format allows;
- ``error``: ValueError/TypeError whose one-line message names the file;
- ``bad-message``: a documented error class, but a message without the file or on many lines;
- ``uncaught``: any other exception (the bug class the issue counts);
- ``silent``: read, but holding a value outside what the format allows (raw 256, a negative
  area, a non-increasing time, a law with negative forces...).

``tests/test_fuzz.py`` runs a few hundred mutations; the command line runs as many as asked:
``python benchmarks/fuzz.py [--n 10000] [--seed 0] [--cli 500]``, printing counts by class
and by reader and examples of each failing class; ``--cli N`` also runs N mutants through
every CLI command that reads their kind of file (info, analyze, apply, report, calibrate,
validate, plot, dynamic apply).
"""

import argparse
import json
import math
import os
import random
import shutil
import sys
import tempfile
import time
import warnings
from collections import Counter
from pathlib import Path

import numpy as np

from tactilecal.calibration import (
    CalibrationResult,
    Equilibration,
    calibrate,
    equilibrate,
    load_points,
    points_from_frames,
)
from tactilecal.dynamic import CorrectionFilter, Evaluation, RationalModel
from tactilecal.io import read_tekscan, read_timeseries, write_tekscan
from tactilecal.simulate import deadweight_session, make_sensor

FAILING = ("bad-message", "uncaught", "silent")
HOSTILE_NUMBERS = ["0", "-5", "-1", "0.5", "256", "1e308", "-1e308", "99999999999999999999",
                   "100000000", "nan", "inf", "-inf", "abc", "", "1_0", "0x10", " ", "B", "1e-320"]
HOSTILE_JSON = [None, -1, 0, -3.5, 1e308, float("nan"), float("inf"), "abc", "", [], [1, 2],
                {}, {"a": 1}, True, 10**30]
REALDATA = Path(os.environ.get("TACTILECAL_REALDATA",
                               Path(__file__).resolve().parents[2] / "shared" / "realdata"))


# ----------------------------------------------------------------------------- seed files
def _cut_export(path, n_frames, out):
    """The first ``n_frames`` frames of a real export, END_FRAME fixed: a fast real seed."""
    lines = path.read_bytes().split(b"\n")
    frames = [i for i, line in enumerate(lines) if line.startswith(b"Frame")]
    stop = frames[n_frames] if len(frames) > n_frames else len(lines)
    kept = lines[:stop]
    last = kept[frames[n_frames - 1]].split(b",")[0].split()[1] if len(frames) >= n_frames \
        else None
    kept = [b"END_FRAME " + last + (b"\r" if line.endswith(b"\r") else b"")
            if line.startswith(b"END_FRAME") and last else line for line in kept]
    end = [line for line in lines if line.strip() == b"@@"][:1]
    out.write_bytes(b"\n".join(kept + end + [b""]))
    return out


def make_seeds(folder):
    """Write the seed files into ``folder``; return ``[(kind, path), ...]``."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    seeds = []
    if REALDATA.is_dir():
        for name in sorted(p.name for p in REALDATA.iterdir() if p.suffix in (".csv", ".asf")):
            seeds.append(("recording", _cut_export(REALDATA / name, 4, folder / f"real_{name}")))
    session = deadweight_session(make_sensor("5051", seed=0), n_patches=3, seed=1)
    manifest = session.write(folder / "session")
    seeds.append(("manifest", manifest))
    seeds.append(("tekscan-cal", _write_cal(folder / "session.cal")))
    recording = next(p for p in manifest.parent.glob("*.csv") if p.name != "manifest.csv")
    seeds.append(("recording", recording))
    # a hand-made raw file: bare "Frame N" lines (no Raw Sum to cross-check) and no UNITS
    bare = folder / "bare.csv"
    bare.write_bytes(b"\n".join(
        line.split(b",")[0] if line.startswith(b"Frame") else line
        for line in recording.read_bytes().split(b"\n") if not line.startswith(b"UNITS")))
    seeds.append(("recording", bare))
    # a calibrated export as write_tekscan writes it: decimals of up to 17 digits, some < 0
    raw = read_tekscan(recording)
    kpa = (raw * 5.9379 - 1.0).assign_attrs({**raw.attrs, "units": "kPa"})
    write_tekscan(kpa, folder / "kpa.csv")
    seeds.append(("recording", folder / "kpa.csv"))
    loadcell = folder / "loadcell.csv"
    loadcell.write_text("Time (ms),Load (N),note\n" + "".join(
        f"{k * 2},{10 + k % 7},s{k}\n" for k in range(40)))
    seeds.append(("timeseries", loadcell))
    frames = np.zeros((3, 4, 4))
    for k, level in enumerate((20, 60, 120)):
        frames[k, 1:3, 1:3] = level
    loads = [4 * 0.0035 * v ** 1.2 for v in (20, 60, 120)]
    cal = folder / "cal.json"
    calibrate(points_from_frames(frames, loads, sensel_area_mm2=1.6129),
              method="power").to_json(cal)
    seeds.append(("calibration", cal))
    eq = folder / "eq.json"
    equilibrate([np.full((2, 3, 3), 100.0) + np.eye(3) * 10]).to_json(eq)
    seeds.append(("equilibration", eq))
    filt = folder / "FILTER.json"
    CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=4000, band_hz=(1, 140)).to_json(filt)
    seeds.append(("filter", filt))
    for name, phase_filter in (  # the filters with phase: a rational model, a measured one
            ("RATIONAL.json", CorrectionFilter("rational", {"zeros": 1, "poles": 1}, 1000.0,
                                               (1.0, 100.0),
                                               rational=RationalModel.from_corners_hz(
                                                   zeros_hz=[40.0], poles_hz=[10.0]))),
            ("WIENER.json", CorrectionFilter("wiener", {"bins": 3}, 1000.0, (1.0, 100.0),
                                             response_f_hz=np.array([10.0, 50.0, 100.0]),
                                             response_gain=np.array([1.1, 1.5 + 0.3j, 2j])))):
        phase_filter.to_json(folder / name)
        seeds.append(("filter", folder / name))
    evaluation = folder / "evaluation.json"
    f_hz = [1.0, 2.0, 5.0, 10.0]
    evaluation.write_text(json.dumps({
        "format": "tactilecal-dynamic-evaluation/1", "lag_s": 0.01, "clock": "fitted",
        "static_factor": 1.2, "fs_hz": 100.0, "band_hz": [1.0, 40.0], "rms_before_N": 3.0,
        "rms_after_N": 1.0, "timing_error_s": 0.0, "above_band_share": 0.01, "f_hz": f_hz,
        "error_before_pct": [-1.0, -3.0, -8.0, -15.0],
        "error_after_pct": [0.1, -0.2, 0.3, 0.5], "phase_before_deg": [-1.0, -2.0, -5.0, -9.0],
        "phase_after_deg": [0.0, 0.1, -0.1, 0.2],
        "window": {"time_s": [0.0, 0.01], "reference": [1.0, 2.0], "sensor": [1.0, 1.5],
                   "corrected": [1.0, 2.0]}}))
    seeds.append(("evaluation", evaluation))
    return seeds


# ----------------------------------------------------------------------------- mutations
def _lines(data):
    return data.split(b"\n")


def _flip(rng, data):
    if not data:
        return data, "empty"
    i = rng.randrange(len(data))
    byte = rng.choice(b",.-+eE0123456789B\r\n\x00\xff_ @F")
    return data[:i] + bytes([byte]) + data[i + 1:], f"byte {i} -> {bytes([byte])!r}"


def _truncate(rng, data):
    i = rng.randrange(len(data) + 1)
    return data[:i], f"truncated at byte {i}"


def _drop_line(rng, data):
    lines = _lines(data)
    i = rng.randrange(len(lines))
    return b"\n".join(lines[:i] + lines[i + 1:]), f"line {i + 1} deleted"


def _repeat_line(rng, data):
    lines = _lines(data)
    i = rng.randrange(len(lines))
    return b"\n".join(lines[:i + 1] + lines[i:]), f"line {i + 1} repeated"


def _insert(rng, data, what):
    i = rng.randrange(len(data) + 1)
    return data[:i] + what + data[i:], f"{what!r} inserted at byte {i}"


def _reencode(rng, data):
    codec = rng.choice(["utf-16", "cp1252", "utf-8-sig", "utf-16-le"])
    text = data.decode("utf-8", errors="replace").replace("\ufffd", "?")
    return text.encode(codec, errors="replace"), f"re-encoded as {codec}"


def _header_value(rng, data):
    lines = _lines(data)
    keyed = [i for i, line in enumerate(lines[:40]) if line[:1].isalpha() and b" " in line
             and not line.startswith((b"Frame", b"ASCII_DATA"))]
    if not keyed:
        return _flip(rng, data)
    i = rng.choice(keyed)
    key = lines[i].split(b" ", 1)[0]
    value = rng.choice(HOSTILE_NUMBERS).encode()
    lines[i] = key + b" " + value + (rng.choice([b"", b" mm", b" cm2", b" KPa"]))
    return b"\n".join(lines), f"header {key.decode()} -> {lines[i].decode(errors='replace')!r}"


def _cell(rng, data):
    lines = _lines(data)
    rows = [i for i, line in enumerate(lines) if b"," in line and not line.startswith(b"Frame")]
    if not rows:
        return _flip(rng, data)
    i = rng.choice(rows)
    cells = lines[i].split(b",")
    j = rng.randrange(len(cells))
    cells[j] = rng.choice(HOSTILE_NUMBERS).encode()
    lines[i] = b",".join(cells)
    return b"\n".join(lines), f"line {i + 1} value {j + 1} -> {cells[j]!r}"


TEXT_MUTATIONS = {
    "flip": _flip, "truncate": _truncate, "drop-line": _drop_line, "repeat-line": _repeat_line,
    "lone-cr": lambda r, d: _insert(r, d, b"\r"), "extra-comma": lambda r, d: _insert(r, d, b","),
    "reencode": _reencode, "header-value": _header_value, "cell": _cell,
}


def _json_paths(obj, prefix=()):
    if isinstance(obj, dict):
        for key, value in obj.items():
            yield prefix + (key,)
            yield from _json_paths(value, prefix + (key,))
    elif isinstance(obj, list) and obj and len(obj) <= 8:
        for k, value in enumerate(obj):
            yield prefix + (k,)
            yield from _json_paths(value, prefix + (k,))


def _json_mutation(rng, data):
    obj = json.loads(data)
    paths = [p for p in _json_paths(obj) if p[0] not in ("points", "levels", "created")]
    path = rng.choice(paths)
    parent = obj
    for key in path[:-1]:
        parent = parent[key]
    if rng.random() < 0.2 and isinstance(parent, dict):
        del parent[path[-1]]
        what = "deleted"
    else:
        parent[path[-1]] = rng.choice(HOSTILE_JSON)
        what = f"-> {parent[path[-1]]!r}"
    return json.dumps(obj).encode(), f"key {'.'.join(map(str, path))} {what}"


def mutate(rng, kind, data):
    """Return ``(mutated bytes, description)`` for a seed of ``kind``."""
    if kind in ("calibration", "equilibration", "filter") and rng.random() < 0.7:
        return _json_mutation(rng, data)
    name = rng.choice(sorted(TEXT_MUTATIONS))
    mutated, what = TEXT_MUTATIONS[name](rng, data)
    return mutated, f"{name}: {what}"


# ----------------------------------------------------------------------------- oracle
def _check_recording(data):
    values = data.values
    attrs = data.attrs
    if attrs.get("units", "raw") == "raw":
        finite = values[np.isfinite(values)]
        if finite.size and (finite.min() < 0 or finite.max() > 255
                            or np.any(finite != np.floor(finite))):
            return "raw value outside whole 0..255"
    if np.isinf(values).any():
        return "infinite value"
    for key in ("sensel_area_mm2", "row_spacing_mm", "col_spacing_mm", "seconds_per_frame"):
        if key in attrs and not (math.isfinite(attrs[key]) and attrs[key] > 0):
            return f"{key} = {attrs[key]}"
    if "noise_threshold" in attrs and not 0 <= attrs["noise_threshold"] <= 255:
        return f"noise_threshold = {attrs['noise_threshold']}"
    times = data.time.values
    if not np.all(np.isfinite(times)) and "seconds_per_frame" in attrs:
        return "non-finite frame time"
    given = times[np.isfinite(times)]
    if np.any(np.diff(given) <= 0):
        return "frame times not increasing"
    return None


def _check_points(points):
    for p in points:
        if not (math.isfinite(p.load_N) and 0 < p.load_N < 1e9):
            return f"load_N = {p.load_N}"
    return None


def _write_cal(path):
    """A Tekscan .cal file of two points (the format of tactilecal.calibration._tekscan_cal)."""
    lines = ["SENSOR_TYPE 5051", "ROWS 44", "COLS 44", "SENSEL_AREA 0.016129 cm2",
             "UNITS PSI", "NOISE_THRESHOLD 3", "CAL_EXP_ENABLED 1", "EQUFLAG 1"]
    for n, (psi, level, count) in enumerate(((40.0, 20, 50), (170.0, 37, 186)), 1):
        hist = np.zeros(256, dtype=int)
        hist[level] = count
        lines += [f"CAL_FPI_{n} {psi}", f"CAL_FPC_{n} 0", f"CAL_RSI_{n} {level * count}",
                  f"CAL_RSC_{n} 0", f"CAL_SM_{n} {count}",
                  f"CAL_HST_{n} " + " ".join(map(str, hist))]
    path.write_text("\r\n".join(lines) + "\r\n")
    return path


def _check_cal_points(points):
    for p in points:
        hist = np.asarray(p.histogram)
        if int(hist[1:].sum()) != p.loaded_cells or float(hist @ np.arange(256)) != p.raw_sum:
            return f"point {p.frame}: histogram differs from its raw sum or loaded sensels"
    return _check_points(points)


def _check_series(series):
    if not np.all(np.isfinite(series.values)) or np.any(np.diff(series.time.values) <= 0):
        return "non-finite value or non-increasing time"
    return None


def _check_calibration(cal):
    table = cal.force_table()
    if not np.all(np.isfinite(table)) or not table[255] > 0:
        return "force table not finite or not positive at 255"
    if cal.model == "power" and not (cal.params["A"] > 0 and cal.params["b"] > 0):
        return f"power law A = {cal.params['A']}, b = {cal.params['b']}"
    if not (np.isnan(cal.sensel_area_mm2) or cal.sensel_area_mm2 > 0):
        return f"sensel area {cal.sensel_area_mm2}"
    return None


def _check_equilibration(eq):
    gain = eq.gain[np.isfinite(eq.gain)]
    return "gain <= 0" if np.any(gain <= 0) or np.isinf(eq.gain).any() else None


def _check_filter(filt):
    grid = np.linspace(0.0, filt.fs_hz / 2, 64)
    ok = (filt.fs_hz > 0 and 0 <= filt.band_hz[0] < filt.band_hz[1] <= filt.fs_hz / 2
          and filt.n_taps >= 1 and all(math.isfinite(v) for v in filt.params.values())
          and np.all(np.isfinite(filt.target(grid))))
    return None if ok else "filter rate, band, taps or parameters out of range"


def _check_evaluation(ev):
    numbers = (ev.rms_before_N, ev.rms_after_N, ev.fs_hz)
    lists = (ev.f_hz, ev.error_before_pct, ev.error_after_pct)
    ok = (all(math.isfinite(v) and v >= 0 for v in numbers) and ev.fs_hz > 0
          and len({len(v) for v in lists}) == 1 and all(np.isfinite(v).all() for v in lists))
    return None if ok else "RMS, rate or per-frequency errors out of range"


READERS = {
    "recording": (read_tekscan, _check_recording),
    "manifest": (load_points, _check_points),
    "tekscan-cal": (load_points, _check_cal_points),
    "timeseries": (read_timeseries, _check_series),
    "calibration": (CalibrationResult.from_json, _check_calibration),
    "equilibration": (Equilibration.from_json, _check_equilibration),
    "filter": (CorrectionFilter.from_json, _check_filter),
    "evaluation": (Evaluation.from_json, _check_evaluation),
}


def classify(kind, path):
    """Open ``path`` with the reader for ``kind``; return ``(class, detail)``."""
    reader, check = READERS[kind]
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # a warning nobody sees is a silent acceptance
            result = reader(path)
    except (ValueError, TypeError) as exc:
        message = str(exc)
        if "\n" in message.strip() or path.name not in message:
            return "bad-message", f"{type(exc).__name__}: {message[:300]}"
        return "error", type(exc).__name__
    except Exception as exc:  # noqa: BLE001 - the point is to count them
        return "uncaught", f"{type(exc).__name__}: {str(exc)[:300]}"
    problem = check(result)
    return ("silent", problem) if problem else ("ok", "")


# ----------------------------------------------------------------------------- driver
def run(n, seed=0, folder=None, progress=False):
    """Run ``n`` mutations; return a list of ``(kind, mutation, class, detail)``."""
    rng = random.Random(seed)
    own = folder is None
    folder = Path(tempfile.mkdtemp(prefix="tactilecal-fuzz-")) if own else Path(folder)
    try:
        seeds = make_seeds(folder / "seeds")
        work = folder / "work"
        outcomes = []
        for k in range(n):
            kind, source = seeds[k % len(seeds)]
            mutated, what = mutate(rng, kind, source.read_bytes())
            # the mutant sits beside its seed so that a manifest finds its recordings
            target = source.parent / f"mutant{source.suffix}" if kind == "manifest" else \
                work / f"mutant_{k % 50}{source.suffix}"
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(mutated)
            outcomes.append((kind, what, *classify(kind, target)))
            if progress and (k + 1) % 1000 == 0:
                print(f"{k + 1} mutations", file=sys.stderr)
        return outcomes
    finally:
        if own:
            shutil.rmtree(folder, ignore_errors=True)


def _cli_commands(kind, mutant, good, out):
    """The CLI commands that read a file of ``kind``, with ``mutant`` in its place."""
    cal, filt = str(good["calibration"]), str(good["filter"])
    m = str(mutant)
    return {
        "recording": [["info", m], ["analyze", m, "--cal", cal],
                      ["apply", cal, m, "--out", f"{out}.nc"],
                      ["report", m, cal, "--out", f"{out}.html"]],
        "manifest": [["calibrate", m], ["calibrate", m, "--method", "zvyagin"],
                     ["validate", cal, m]],
        "tekscan-cal": [["calibrate", m, "--method", "linear"], ["validate", cal, m]],
        "timeseries": [["dynamic", "apply", filt, m, "--out", f"{out}.csv"]],
        "calibration": [["apply", m, str(good["raw"]), "--out", f"{out}.nc"],
                        ["validate", m, str(good["manifest"])], ["plot", m, "--out", str(out)]],
        "equilibration": [["calibrate", str(good["manifest"]), "--equilibration", m]],
        "filter": [["dynamic", "apply", m, str(good["timeseries"]), "--out", f"{out}.csv"]],
        "evaluation": [["report", m, "--out", f"{out}.html"]],
    }[kind]


def _run_cli(argv):
    """Run ``python -m tactilecal -q ARGV`` as a user would; return (exit code, stderr)."""
    import subprocess

    done = subprocess.run([sys.executable, "-m", "tactilecal", "-q", *argv],
                          capture_output=True, text=True, check=False)
    return done.returncode, done.stderr.strip()


def run_cli(n, seed=0, folder=None, run=None, keep=None):
    """Run ``n`` mutants through the CLI commands that read them; return the failures.

    Each command runs in its own process (``python -m tactilecal``), as a user runs it: the
    exit code and standard error are the real ones (benchmarks do not import the CLI).
    ``run(argv) -> (exit code, stderr)`` replaces the process (the tests run the commands in
    their own process, in seconds); ``keep(argv)`` chooses the command lines run (all).

    A failure is an exit code other than 0/1/2, a traceback, or an error (exit 1) that takes
    more than one line. Returns ``(n_runs, [(kind, mutation, argv, stderr), ...])``.
    """
    rng = random.Random(seed)
    own = folder is None
    folder = Path(tempfile.mkdtemp(prefix="tactilecal-clifuzz-")) if own else Path(folder)
    try:
        seeds = make_seeds(folder / "seeds")
        by_kind = {}
        for kind, path in seeds:
            by_kind.setdefault(kind, []).append(path)
        good = {kind: paths[0] for kind, paths in by_kind.items()}
        good["raw"] = next(p for p in by_kind["recording"] if p.name == "bare.csv")
        runs, failures = 0, []
        for k in range(n):
            kind, source = seeds[k % len(seeds)]
            mutated, what = mutate(rng, kind, source.read_bytes())
            mutant = source.parent / f"mutant{source.suffix}" if kind == "manifest" else \
                folder / f"mutant_{k % 20}{source.suffix}"
            mutant.write_bytes(mutated)
            for argv in filter(keep, _cli_commands(kind, mutant, good, folder / f"out_{k}")):
                code, text = (run or _run_cli)(argv)
                runs += 1
                errors = [line for line in text.splitlines() if ": warning: " not in line
                          and not line.startswith("removed ")]
                if code not in (0, 1, 2) or "Traceback" in text or (code == 1
                                                                   and len(errors) != 1):
                    failures.append((kind, what, " ".join(argv[:1]), text[:300]))
        return runs, failures
    finally:
        if own:
            shutil.rmtree(folder, ignore_errors=True)


def report(outcomes, examples=5):
    """Return the table of counts by class and reader, and failing examples of each kind."""
    by_class = Counter(o[2] for o in outcomes)
    lines = [f"{len(outcomes)} mutations: " + ", ".join(f"{c} {by_class.get(c, 0)}" for c in
                                                       ("ok", "error", *FAILING))]
    kinds = sorted({o[0] for o in outcomes})
    lines.append(f"{'reader':<14}" + "".join(f"{c:>12}" for c in ("ok", "error", *FAILING)))
    for kind in kinds:
        counts = Counter(o[2] for o in outcomes if o[0] == kind)
        lines.append(f"{kind:<14}" + "".join(f"{counts.get(c, 0):>12}"
                                             for c in ("ok", "error", *FAILING)))
    for cls in FAILING:
        seen = set()
        for kind, what, got, detail in outcomes:
            key = (kind, detail[:45])
            if got == cls and key not in seen and len(seen) < examples:
                seen.add(key)
                lines.append(f"{cls}: {kind}, {what}: {detail}")
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=10000, help="mutations (10000)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--cli", type=int, default=0, metavar="N",
                        help="also run N mutants through the CLI commands that read them")
    args = parser.parse_args()
    start = time.perf_counter()
    if args.cli:
        runs, failures = run_cli(args.cli, args.seed)
        print(f"CLI: {args.cli} mutants, {runs} command runs, {len(failures)} failures "
              "(exit code not 0/1/2, traceback, or an error over more than one line)")
        for failure in failures[:10]:
            print("  ", *failure)
    outcomes = run(args.n, args.seed, progress=True)
    print(report(outcomes))
    print(f"{time.perf_counter() - start:.0f} s; real exports "
          f"{'used' if REALDATA.is_dir() else 'absent'} ({REALDATA})")
    return 1 if any(o[2] in FAILING for o in outcomes) else 0


if __name__ == "__main__":
    sys.exit(main())
