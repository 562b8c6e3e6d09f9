"""Shared pytest fixtures.

Real Tekscan exports live outside the repository in ``../shared/realdata/`` (next to the
checkout); set ``TACTILECAL_REALDATA`` to point elsewhere. Tests that need them skip with
a reason when the folder is absent.
"""

import os
from pathlib import Path

# One BLAS thread per test process. The README runs the tests on every core (pytest-xdist,
# one worker per core), so a BLAS thread pool in each worker oversubscribes the cores and
# OpenBLAS's idle threads spin: a (2000, 255) matrix-vector product took 8 ms instead of
# 0.1 ms on 2 busy cores, and the movie calibration tests three times as long. The xdist
# workers and the tests' subprocesses start after this and inherit it (in a run without
# xdist it acts only if no plugin has loaded numpy yet). A value the caller set is kept.
for _name in ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "OMP_NUM_THREADS"):
    os.environ.setdefault(_name, "1")

import pytest  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
REALDATA = Path(os.environ.get("TACTILECAL_REALDATA", REPO.parent / "shared" / "realdata"))


def pytest_collect_file(file_path, parent):
    """Load the Hypothesis profile before the first test module is imported.

    The "fast" profile runs in the suite, each property test a second or two, the same
    examples every run; TACTILECAL_HYPOTHESIS=long runs many more, random ones (minutes:
    python -m pytest tests/test_properties_*.py with TACTILECAL_HYPOTHESIS=long). A profile
    given with ``--hypothesis-profile`` is left as Hypothesis's plugin loaded it. Loaded
    here, as the first file of this folder is collected, rather than at this file's import:
    pytest-xdist's controller collects nothing, and its importing Hypothesis (whose modules
    pytest rewrites) delayed the start of the workers.
    """
    if parent.config.getoption("hypothesis_profile", None) is not None:
        return
    from hypothesis import settings

    name = os.environ.get("TACTILECAL_HYPOTHESIS", "fast")
    if settings.get_current_profile_name() != name:
        _register_hypothesis_profiles()
        settings.load_profile(name)


def pytest_configure(config):
    """Register the profiles before Hypothesis's plugin loads one named on the command line."""
    if config.getoption("hypothesis_profile", None) in ("fast", "long"):
        _register_hypothesis_profiles()


def pytest_unconfigure(config):
    """Leave the objects of the session out of the collections of the interpreter's exit.

    Nothing left needs collecting once the session is over: each process (the xdist
    workers and controller) then exits without touring every object of the session.
    """
    import gc

    gc.freeze()


def _register_hypothesis_profiles():
    from hypothesis import HealthCheck, settings

    settings.register_profile("fast", max_examples=30, deadline=None, derandomize=True,
                              database=None, print_blob=True,
                              suppress_health_check=[HealthCheck.too_slow])
    settings.register_profile("long", max_examples=2000, deadline=None, print_blob=True,
                              suppress_health_check=[HealthCheck.too_slow])


@pytest.fixture(scope="session")
def realdata():
    """Folder holding the real Tekscan exports (skip when absent)."""
    if not REALDATA.is_dir():
        pytest.skip(f"real Tekscan exports not found at {REALDATA}")
    return REALDATA


@pytest.fixture(scope="session")
def iscan_csv(realdata):
    """The real I-Scan 6.10I movie export (309 x 28 x 28, raw)."""
    return realdata / "pressuRe_iscan_test.csv"


@pytest.fixture(scope="session")
def fscan_asf(realdata):
    """The real F-Scan 6.33 walking-step export (205 x 60 x 21, kPa, CRLF)."""
    return realdata / "footPress_FrasP01L.asf"


@pytest.fixture(scope="session")
def fscan_right_asf(realdata):
    """The real F-Scan 6.33 export of the other foot (FrasP01R: 1-point, 2.171 kPa/count)."""
    return realdata / "footPress_FrasP01R.asf"


@pytest.fixture
def assert_names_by_bytes():
    """Check that a provenance record lists exactly some files, each with its SHA-256."""
    import hashlib

    import tactilecal

    def check(prov, paths):
        assert prov["tactilecal_version"] == tactilecal.__version__
        assert {i["path"]: i["sha256"] for i in prov["inputs"]} == {
            str(Path(p).resolve()): hashlib.sha256(Path(p).read_bytes()).hexdigest()
            for p in paths}

    return check


@pytest.fixture(scope="session")
def fuzz():
    """The fuzzing engine ``benchmarks/fuzz.py`` (a script, so loaded from its file)."""
    import importlib.util

    path = Path(__file__).resolve().parents[1] / "benchmarks" / "fuzz.py"
    spec = importlib.util.spec_from_file_location("tactilecal_fuzz", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
