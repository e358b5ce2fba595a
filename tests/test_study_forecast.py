"""``forecast``: when the runs left of a study are trained by a number of
processes that take them as ``run_study`` does (in order, a run once the runs
it builds on are finished, a held run first by its holder), and how long at
the end fewer runs train than there are processes."""

import pytest

from locustjump.runs.study_plan import Forecast, Job, forecast


def test_one_process_trains_them_one_after_another():
    assert forecast([Job(3.0), Job(4.0), Job(5.0)], 1) == Forecast(12.0, 0.0)


def test_an_odd_run_out_leaves_a_process_idle_at_the_end():
    assert forecast([Job(10.0)] * 3, 2) == Forecast(20.0, 10.0)
    assert forecast([Job(10.0)] * 4, 2) == Forecast(20.0, 0.0)


def test_a_held_run_is_finished_by_its_holder_first():
    # the free process takes the 10 s run at once; the holder frees at 5
    assert forecast([Job(5.0, held=True), Job(10.0)], 2) == Forecast(10.0, 5.0)
    # both train from the start: the tail is what the longer one has left
    assert forecast([Job(0.5, held=True), Job(2.0)], 2) == Forecast(2.0, 1.5)
    # held runs end first even when they stand later in the order
    assert forecast([Job(4.0), Job(1.0, held=True)], 1) == Forecast(5.0, 0.0)


def test_a_run_waits_for_the_runs_it_builds_on():
    """Run 1 builds on run 0: the second process takes run 2 instead, then
    waits for run 0 to finish; the first takes run 1 at 3 s."""
    jobs = [Job(3.0), Job(10.0, after=(0,)), Job(1.0)]
    assert forecast(jobs, 2) == Forecast(13.0, 12.0)
    # in order on one process, nothing waits
    assert forecast(jobs, 1) == Forecast(14.0, 0.0)


def test_fewer_runs_than_processes_and_none_at_all():
    assert forecast([Job(4.0)], 3) == Forecast(4.0, 4.0)
    assert forecast([], 2) == Forecast(0.0, 0.0)


def test_a_run_built_on_one_never_trained_is_an_error():
    with pytest.raises(ValueError, match="job 0 builds on a job never trained"):
        forecast([Job(1.0, after=(5,))], 1)


def test_fewer_processes_than_held_runs_is_an_error():
    with pytest.raises(ValueError, match="processes: 1, fewer than the 2 held"):
        forecast([Job(1.0, held=True), Job(1.0, held=True)], 1)
    with pytest.raises(ValueError, match="processes: 0, not >= 1"):
        forecast([Job(1.0)], 0)
