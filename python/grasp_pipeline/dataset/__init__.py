"""Demonstration datasets: the reference policy's episodes recorded as LeRobot episodes.

``grasp-pipeline record`` (:mod:`.record_command`) runs jobs of episodes in worker processes; in
each (:mod:`.record_job`), the learning environment's episode is played by the reference policy
and recorded through the environment's own observations and actions
(:mod:`.episode_recording`, :mod:`.episode`); each kept episode is written there through
LeRobot's own writer (:mod:`.lerobot_writer`, :mod:`.shards`; optional extra
``grasp_pipeline[dataset]``) and the parent merges them into one LeRobot dataset (format v3.0)
without ever leaving a half-written one (:mod:`.dataset_folder`).
"""
