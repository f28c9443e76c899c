"""Demonstration datasets: the pipeline's picks recorded as LeRobot episodes.

``grasp-pipeline record`` (:mod:`.record_command`) runs declutter rounds in worker processes;
in each, an :class:`.episode_recorder.EpisodeRecorder` on the run's event stream samples the
robot and renders its own camera views at the recording rate, one episode per pick
(:mod:`.episode`); the parent writes one LeRobot dataset (format v3.0) through LeRobot's own
writer (:mod:`.lerobot_writer`, optional extra ``grasp_pipeline[dataset]``).
"""
