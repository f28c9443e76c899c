"""The test session is a composition root like a console command: it chooses the headless GL
backend before anything imports MuJoCo (``MUJOCO_GL`` from the environment is respected)."""

from grasp_pipeline.sim.gl_backend import configure_gl

configure_gl()

#: The shared ``record`` run of the dataset and learning tests (fixture ``recorded_dataset``).
pytest_plugins = ["recorded"]
