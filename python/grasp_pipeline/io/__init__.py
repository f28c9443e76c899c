"""Point-cloud files: PCD / PLY through PCL's own reader and writer (``grasp_pipeline._pcl_io``),
NPY through numpy. See :mod:`grasp_pipeline.io.cloud_io`."""

from .cloud_io import SUPPORTED_EXTENSIONS, Cloud, load_cloud, save_pcd

__all__ = ["SUPPORTED_EXTENSIONS", "Cloud", "load_cloud", "save_pcd"]
