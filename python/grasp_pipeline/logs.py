"""Logging set-up of the console commands and their worker processes (one place).

The default level shows stages and decisions; per-frame lines (view labels) are DEBUG, and
third-party chatter (TOPP-RA logs every parameterisation at INFO; PyOpenGL's accelerate
notice) is shown only at DEBUG.
"""

from __future__ import annotations

import logging

#: Third-party loggers kept at WARNING unless the user asks for DEBUG.
QUIET_LOGGERS = ("toppra", "OpenGL", "matplotlib", "PIL")


def setup_logging(level: int, tag: str = "") -> None:
    """Configure the root logger once per process; ``tag`` (e.g. ``"[scene 3] "``) prefixes
    every line of a worker process."""
    logging.basicConfig(level=level, format=f"%(asctime)s %(levelname)s {tag}%(name)s: %(message)s")
    for name in QUIET_LOGGERS:
        logging.getLogger(name).setLevel(max(logging.WARNING, level))


def retag_logging(tag: str) -> None:
    """Change the prefix of every line of this process (a worker starting its next job)."""
    fmt = logging.Formatter(f"%(asctime)s %(levelname)s {tag}%(name)s: %(message)s")
    for handler in logging.getLogger().handlers:
        handler.setFormatter(fmt)
