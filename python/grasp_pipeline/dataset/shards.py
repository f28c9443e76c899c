"""Episodes written where they are recorded, then merged into one dataset with LeRobot's tools.

Every kept episode becomes a LeRobot dataset of its own (a *shard*) in the worker that records
it: :func:`write_shard` writes it through LeRobot's writer (:class:`.lerobot_writer.LeRobotWriter`:
video encoding included) into ``<name>.writing`` and renames that to ``<name>`` once finished,
so a folder without the suffix is always a complete shard. The parent finds the finished
shards (:func:`finished_shards`, in episode order) and merges them with LeRobot's
``aggregate_datasets`` (:func:`merge_shards`: data and videos are copied, videos concatenated
without re-encoding), adding the list of episode outcomes.
"""

from __future__ import annotations

import json
import logging
import re
import shutil
from dataclasses import dataclass
from pathlib import Path

from .lerobot_writer import OUTCOMES_FILE, LeRobotWriter

log = logging.getLogger(__name__)

#: Suffix of a shard that is being written.
WRITING_SUFFIX = ".writing"
_SHARD = re.compile(r"episode_(\d+)_scene_(\d+)")


def shard_name(index: int, scene_seed: int) -> str:
    return f"episode_{index:05d}_scene_{scene_seed}"


@dataclass(frozen=True)
class Shard:
    """A finished shard: its episode index (the attempt's), folder and outcome."""

    index: int
    root: Path
    outcome: dict


def write_shard(work: Path, index: int, scene_seed: int, episode, extra: dict, config,
                depth: bool) -> Path:
    """Write ``episode`` as the one-episode dataset ``work/<shard_name>``; returns its folder."""
    final = Path(work) / shard_name(index, scene_seed)
    tmp = final.with_name(final.name + WRITING_SUFFIX)
    shutil.rmtree(tmp, ignore_errors=True)
    writer = LeRobotWriter(tmp, config, depth)
    writer.add(episode, extra)
    writer.close()
    tmp.rename(final)
    return final


def finished_shards(work: Path) -> list[Shard]:
    """The finished shards in ``work``, by episode index."""
    out = []
    for p in Path(work).glob("episode_*") if Path(work).is_dir() else []:
        m = _SHARD.fullmatch(p.name)
        outcomes = p / OUTCOMES_FILE
        if m is None or not outcomes.is_file():
            continue
        (outcome,) = [json.loads(line) for line in outcomes.read_text().splitlines() if line.strip()]
        out.append(Shard(int(m.group(1)), p, outcome))
    return sorted(out, key=lambda s: s.index)


def merge_shards(shards: list[Shard], root: Path, repo_id: str, video_file_size_mb: float) -> list[dict]:
    """One dataset at ``root`` (which must not exist) of the shards' episodes, in their order,
    with the outcome list; returns the outcomes (``episode_index`` renumbered). Video files
    hold up to ``video_file_size_mb`` (LeRobot appends each episode by rewriting the file it
    joins: bounded files keep the merge linear in the episodes)."""
    from lerobot.datasets.aggregate import aggregate_datasets

    aggregate_datasets(repo_ids=[repo_id] * len(shards), aggr_repo_id=repo_id,
                       roots=[s.root for s in shards], aggr_root=Path(root),
                       video_files_size_in_mb=float(video_file_size_mb))
    outcomes = [{**s.outcome, "episode_index": k} for k, s in enumerate(shards)]
    path = Path(root) / OUTCOMES_FILE
    path.write_text("".join(json.dumps(o) + "\n" for o in outcomes))
    return outcomes
