"""Run outputs a user looks at: RViz-like PNG snapshots (:mod:`.snapshot`) and videos (:mod:`.video`).

Imported lazily (matplotlib / imageio load only when used)."""
