"""Fault injection for tests that run the command line in real processes: a signal at the start
of one named function, in whichever process (the command or one of its spawned workers) calls
it first.

``fault_env(tmp_path, "grasp_pipeline.bench.clutter_plots:write_plots", "SIGTERM", "main")``
returns environment variables that make Python load this folder's ``sitecustomize`` hook (a
generated file, first on ``PYTHONPATH``): when the module is imported, its function is wrapped so
that its first call, in the whole process tree, sends the signal before running the function
itself — the signal lands while the function runs, as a user's Ctrl-C or ``kill`` would.
Targets: ``self`` (the calling process), ``main`` (the command: start it with
``start_new_session=True`` so it leads the process group) and ``group`` (every process of the
command, as Ctrl-C in a terminal does). Nothing of the product is replaced or mocked.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
from pathlib import Path

EXE = Path(sys.executable).parent / "grasp-pipeline"

HOOK = '''
import importlib.abc, importlib.util, os, signal, sys

_spec = os.environ.get("GP_FAULT")
if _spec:
    _module, _function, _signal, _target = _spec.split(":")

    def _fire():
        try:
            fd = os.open(os.environ["GP_FAULT_ONCE"], os.O_CREAT | os.O_EXCL | os.O_WRONLY)
        except FileExistsError:
            return
        os.close(fd)
        sig = getattr(signal, _signal)
        if _target == "group":
            os.killpg(os.getpgrp(), sig)
        else:
            os.kill(os.getpgrp() if _target == "main" else os.getpid(), sig)

    def _wrap(function):
        def faulty(*args, **kwargs):
            _fire()
            return function(*args, **kwargs)
        return faulty

    class _Loader(importlib.abc.Loader):
        def __init__(self, inner):
            self.inner = inner

        def create_module(self, spec):
            return self.inner.create_module(spec)

        def exec_module(self, module):
            self.inner.exec_module(module)
            setattr(module, _function, _wrap(getattr(module, _function)))

    class _Finder(importlib.abc.MetaPathFinder):
        def find_spec(self, name, path, target=None):
            if name != _module:
                return None
            sys.meta_path.remove(self)
            try:
                spec = importlib.util.find_spec(name)
            finally:
                sys.meta_path.insert(0, self)
            spec.loader = _Loader(spec.loader)
            return spec

    sys.meta_path.insert(0, _Finder())
'''


def fault_env(tmp_path: Path, where: str, sig: str, target: str) -> dict:
    """Environment additions that inject the fault (see the module doc)."""
    hook_dir = tmp_path / "fault_hook"
    hook_dir.mkdir(exist_ok=True)
    (hook_dir / "sitecustomize.py").write_text(HOOK)
    path = clean_env(tmp_path).get("PYTHONPATH", "")
    return {"GP_FAULT": f"{where}:{sig}:{target}", "GP_FAULT_ONCE": str(tmp_path / "fault_fired"),
            "PYTHONPATH": str(hook_dir) + (os.pathsep + path if path else "")}


def clean_env(home: Path, extra: dict | None = None) -> dict:
    """A plain user's environment (as a shell gives it) plus ``extra``."""
    env = {"PATH": f"{EXE.parent}:/usr/bin:/bin", "HOME": str(home), "LANG": "C.UTF-8"}
    if os.environ.get("PYTHONPATH"):  # a source checkout under test (absolute: the cwd changes)
        env["PYTHONPATH"] = os.pathsep.join(os.path.abspath(p) for p in
                                            os.environ["PYTHONPATH"].split(os.pathsep) if p)
    env.update(extra or {})
    return env


def _terminal_sigint() -> None:
    """SIGINT as a foreground process of an interactive shell has it (a runner started in the
    background passes SIGINT on ignored, and Python keeps an ignored SIGINT ignored)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def start(args: list[str], cwd: Path, env: dict) -> subprocess.Popen:
    """The command as a user starts it from a terminal, leading its own process group."""
    return subprocess.Popen([str(EXE), *args], cwd=cwd, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, stdin=subprocess.DEVNULL,
                            preexec_fn=_terminal_sigint, start_new_session=True)


def leftovers(folder: Path) -> list[str]:
    """Temporary files and output markers left under ``folder`` (there should be none)."""
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*")
                  if p.name.endswith((".tmp", ".lock")) or ".tmp-" in p.name)
