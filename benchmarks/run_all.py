"""Run the scaling benchmarks of issue 16 in one command, one script after another.

Each script runs in its own process with the arguments of the scaling table in
``benchmarks/README.md`` and writes its ratios (to a baseline measured in the same run) to
stdout; this runner adds a header per script and stops at the first failure. ``--quick``
runs the small sizes only (minutes, to check that everything runs); without it the full
table takes hours on two cores. ``--only NAME ...`` runs some of them.

    python benchmarks/run_all.py --quick
    python benchmarks/run_all.py --only read movie > scaling.txt
"""

import argparse
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent

#: name -> (script, full arguments, quick arguments)
RUNS = {
    "read": ("bench_scale_read.py", ["--sizes", "10000,100000", "--large", "1000000",
                                     "--repeat", "3"],
             ["--sizes", "2000", "--eager-only", "--repeat", "1"]),
    "movie": ("bench_movie.py", ["--sizes", "10000", "100000", "1000000", "--repeat", "3"],
              ["--sizes", "2000", "--repeat", "1"]),
    "zvyagin": ("bench_zvyagin_scale.py", ["--sizes", "45", "150", "1000", "--repeat", "3"],
                ["--sizes", "45", "--repeat", "1"]),
    "filter": ("bench_dynamic.py", ["--skip-accuracy", "--frames", "8192", "32768", "131072",
                                    "--chunks", "8192", "16384", "--repeat", "3"],
               ["--skip-accuracy", "--frames", "8192", "--chunks", "4096", "--repeat", "1"]),
    "cluster": ("bench_dynamic.py", ["--skip-accuracy", "--skip-throughput", "--cluster",
                                     "--frames", "8192", "32768", "131072", "--chunk-frames",
                                     "8192", "--repeat", "2"],
                ["--skip-accuracy", "--skip-throughput", "--cluster", "--frames", "8192",
                 "--chunk-frames", "4096", "--repeat", "1"]),
}


def main(argv=None):
    """Run the chosen benchmarks; return the first non-zero exit code (0 if all ran)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small sizes only")
    parser.add_argument("--only", nargs="+", choices=list(RUNS), default=list(RUNS),
                        metavar="NAME", help=f"some of {', '.join(RUNS)}")
    args = parser.parse_args(argv)
    for name in args.only:
        script, full, quick = RUNS[name]
        command = [sys.executable, str(HERE / script), *(quick if args.quick else full)]
        print(f"\n===== {name}: {' '.join(command[1:])}", flush=True)
        start = time.perf_counter()
        code = subprocess.call(command)
        print(f"===== {name}: exit {code} after {time.perf_counter() - start:.0f} s", flush=True)
        if code:
            return code
    return 0


if __name__ == "__main__":
    sys.exit(main())
