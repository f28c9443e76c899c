"""Objects for the simulated world: meshes with convex collision parts.

* :mod:`.model` — :class:`~.model.ObjectModel`, one object as the world builder needs it
  (convex collision parts, a visual mesh, colour, name), and :class:`~.model.MeshError`.
* :mod:`.shapes` / :mod:`.builtin` — the built-in procedural object set (no download).
* :mod:`.mesh_object` — objects from OBJ/STL files and VGN/GIGA URDF folders.

Nothing here imports MuJoCo; meshes are ``trimesh.Trimesh`` in metres, z up, the object's
frame at the centre of its bounding box's bottom face (it stands on z = 0).
"""
