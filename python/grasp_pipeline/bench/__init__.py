"""Benchmarks: commands that measure the product in one run and write what they measured.

:mod:`.registry` lists them (``grasp-pipeline bench <name>``: arguments, entry point, what it
prints). Each entry point returns a typed result (a frozen dataclass: ``*_result`` modules, or
beside its benchmark) that :mod:`grasp_pipeline.report.serialize` writes as JSON; the figures
they share are in :mod:`.figures`; the scene benchmarks run their scenes or rounds as jobs
(:mod:`.jobs`, :mod:`.scheduler`, :mod:`.ray_backend`) and write their files with
:mod:`.results_files`."""
