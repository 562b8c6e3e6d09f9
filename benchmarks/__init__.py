"""The benchmark suite of tactilecal, run by asv (``asv run``; see ``benchmarks/README.md``)."""
