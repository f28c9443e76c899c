"""How many jobs ``record`` starts: enough for every episode at first (no worker waits for a
batch to end), then as many as the kept share says are missing."""

from grasp_pipeline.dataset.record_command import _batch


def _rows(played: int, kept: int) -> list:
    eps = [{"shard": "x" if i < kept else None} for i in range(played)]
    return [{"episodes": eps}]


def test_first_batch_holds_every_episode_then_the_kept_share_decides():
    a = {"per_job": 4, "workers": 2}
    assert _batch(24, [], a) == 6                 # 24 episodes in jobs of 4, on 2 workers
    assert _batch(2, [], a) == 2                  # at least one job per worker
    assert _batch(5, [], {"per_job": 4, "workers": 3}) == 3
    assert _batch(8, _rows(16, 8), a) == 4        # half kept: 8 more need 16 played = 4 jobs
    assert _batch(8, _rows(16, 0), a) == 2        # nothing kept yet: one job per worker


def test_a_small_request_plays_jobs_no_larger_than_it_needs():
    from grasp_pipeline.dataset.record_command import job_size

    assert job_size(4, 2, 1) == 2      # 2 episodes on 1 worker: one job of 2, not 4 played
    assert job_size(4, 2, 2) == 1      # ... on 2 workers: a job of 1 each
    assert job_size(4, 16, 2) == 4     # a large request keeps the configured size
    assert job_size(4, 5, 2) == 3
    assert job_size(1, 100, 8) == 1
