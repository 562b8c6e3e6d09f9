"""Seeded mutation fuzzing of every reader (issue 11): no traceback, nothing silently accepted.

The engine is ``benchmarks/fuzz.py`` (its command line runs 10,000 mutations); here a few
hundred run in seconds, on the real exports when ``../shared/realdata`` is present and on
files tactilecal writes itself either way. The property-based tests
(``tests/test_properties_*.py``) generate the files and their edits; this engine mutates
the real exports and runs the mutants through every command, also as separate processes
(``@pytest.mark.slow``: what a user's terminal shows, interpreter messages included).
"""

import os
import random

import pytest

from tactilecal.cli import main


def test_mutated_inputs_give_documented_errors_or_valid_data(fuzz, tmp_path):
    outcomes = fuzz.run(200, seed=11, folder=tmp_path)
    failing = [o for o in outcomes if o[2] in fuzz.FAILING]
    assert not failing, fuzz.report(outcomes)
    classes = {o[2] for o in outcomes}
    assert {"ok", "error"} <= classes  # the mutations both break files and leave some readable
    assert {o[0] for o in outcomes} == set(fuzz.READERS)  # every reader was fuzzed


def test_mutated_recordings_through_the_cli_exit_0_or_1_with_one_line(fuzz, tmp_path, capsys):
    seeds = [s for s in fuzz.make_seeds(tmp_path / "seeds") if s[0] == "recording"]
    for _, source in seeds:  # the seeds themselves are valid
        assert main(["-q", "info", str(source), "--json"]) == 0
        capsys.readouterr()
    rng = random.Random(5)
    codes = []
    for k in range(40):
        _, source = seeds[k % len(seeds)]
        mutated, what = fuzz.mutate(rng, "recording", source.read_bytes())
        path = tmp_path / f"m{k}{source.suffix}"
        path.write_bytes(mutated)
        code = main(["-q", "info", str(path), "--json"])
        err = capsys.readouterr().err.strip()
        assert code in (0, 1), what
        if code == 1:
            assert len(err.splitlines()) == 1 and path.name in err, (what, err)
        codes.append(code)
    assert 1 in codes  # the mutations did break files


def _run_in_process(argv, capsys):
    code = main(["-q", *argv])
    return code, capsys.readouterr().err.strip()


def test_mutated_inputs_through_every_reading_command_fail_in_one_line(fuzz, tmp_path, capsys):
    """Each command in this process (``tactilecal.cli.main``): 30 runs in seconds.

    ``report`` of a mutated recording (3 s each, drawing its figures) runs only in the slow
    test; ``info``, ``analyze`` and ``apply`` read those recordings here.
    """
    runs, failures = fuzz.run_cli(
        16, seed=3, folder=tmp_path, run=lambda argv: _run_in_process(argv, capsys),
        keep=lambda argv: argv[0] != "report" or argv[1].endswith(".json"))
    assert runs >= 30 and not failures, failures[:3]


@pytest.mark.slow
@pytest.mark.skipif(os.environ.get("TACTILECAL_HYPOTHESIS") != "long",
                    reason="minutes (a process per command): run with TACTILECAL_HYPOTHESIS=long")
def test_mutated_inputs_through_every_command_as_processes_fail_in_one_line(fuzz, tmp_path):
    """The same as a user runs them: ``python -m tactilecal`` (a process each, 1-2 s)."""
    runs, failures = fuzz.run_cli(14, seed=3, folder=tmp_path)
    assert runs > 30 and not failures, failures[:3]
