"""Run outputs a user looks at: RViz-like PNG snapshots (:mod:`.snapshot`), videos
(:mod:`.video`) and 3-D Rerun recordings (:mod:`.rerun_recorder`, read back with
:mod:`.rerun_summary`).

Imported lazily (matplotlib / imageio / the Rerun SDK load only when used)."""
