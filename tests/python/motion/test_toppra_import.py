"""TOPP-RA is imported without matplotlib's pyplot, and toppra's plotting still reaches it."""

import subprocess
import sys
import textwrap


def _run(code: str) -> str:
    """Run ``code`` in a fresh interpreter (nothing imported yet) and return its stdout."""
    done = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    return done.stdout.strip()


def test_toppra_comes_without_matplotlib():
    out = _run("""
        import sys
        from grasp_pipeline.motion.toppra_import import import_toppra
        toppra = import_toppra()
        assert hasattr(toppra.algorithm, "TOPPRA") and hasattr(toppra.constraint, "JointVelocityConstraint")
        print(sorted(m for m in sys.modules if m == "matplotlib" or m.startswith("matplotlib.")))
    """)
    assert out == "[]"


def test_toppra_plots_with_the_real_pyplot_and_later_imports_get_it():
    out = _run("""
        import sys
        from grasp_pipeline.motion.toppra_import import import_toppra
        import_toppra()
        import toppra.algorithm.algorithm as algorithm
        import matplotlib
        import matplotlib.pyplot as pyplot
        assert type(pyplot).__name__ == "module" and hasattr(matplotlib, "use")
        assert algorithm.plt.plot is pyplot.plot   # the stand-in hands out the real pyplot's
        print(sys.modules["matplotlib.pyplot"] is pyplot)
    """)
    assert out == "True"


def test_an_imported_matplotlib_is_left_as_it_is():
    out = _run("""
        import sys
        import matplotlib
        from grasp_pipeline.motion.toppra_import import import_toppra
        import_toppra()
        print(sys.modules["matplotlib"] is matplotlib, "matplotlib.pyplot" in sys.modules)
    """)
    assert out == "True False"
