"""What registering the ``.tactile`` accessor at ``import tactilecal`` would cost.

The accessor needs xarray imported; ``import tactilecal`` does not import it (the names are
lazy). Each variant runs in a fresh interpreter, interleaved, ``--repeat`` times; the report
is the median of each and its ratio to ``python -c pass`` and to ``import tactilecal``.

    python benchmarks/bench_import.py --repeat 7
"""

import argparse
import subprocess
import sys
import time

import numpy as np

VARIANTS = {
    "python -c pass": "pass",
    "import tactilecal": "import tactilecal",
    "import tactilecal + xarray": "import tactilecal, xarray",
    "import tactilecal.analysis (registers)": "import tactilecal.analysis",
}


def _once(code):
    start = time.perf_counter()
    subprocess.run([sys.executable, "-c", code], check=True)
    return time.perf_counter() - start


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7)
    args = parser.parse_args(argv)
    times = {name: [] for name in VARIANTS}
    for _ in range(args.repeat):  # interleaved: the machine's load hits every variant alike
        for name, code in VARIANTS.items():
            times[name].append(_once(code))
    median = {name: float(np.median(t)) for name, t in times.items()}
    base, lib = median["python -c pass"], median["import tactilecal"]
    print(f"median of {args.repeat}, fresh interpreter each")
    for name, t in median.items():
        print(f"{name:<40} {t:7.3f} s  x{t / base:6.1f} of 'pass'  x{t / lib:6.1f} of "
              "'import tactilecal'")


if __name__ == "__main__":
    main()
