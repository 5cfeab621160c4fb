"""Shared test helpers: small worlds built in memory."""

from __future__ import annotations

import os

import pytest

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
os.environ.setdefault("SDL_AUDIODRIVER", "dummy")

from swarmsim.world import World, world_from_dict

SLOW_TESTS = frozenset({
    # whole runs of a few thousand ticks, each 8 s or more on 2 cores (pytest --durations)
    "test_a_mover_stops_for_another_groups_mover_and_resumes_when_it_has_gone",
    "test_cvt_spreads_a_crowd_all_the_way",
    "test_every_d_cover_run_terminates_by_a_stop_rule",
    "test_noise_changes_results_only_when_set",
    "test_a_run_decided_through_columns_is_the_run_decided_robot_by_robot",
    "test_makes_progress_without_overlap",
    "test_two_groups_meeting_head_on_resolve_without_deadlock",
    "test_sleeping_changes_nothing_but_saves_work",
    "test_same_seed_same_run_in_two_processes",
    "test_sleeping_changes_nothing",
    "test_movers_with_no_place_they_can_reach_end_standing",
    "test_runs_that_share_an_id_are_the_same_tick_for_tick",
    "test_same_seed_same_run_and_sleep_changes_nothing",
    "test_study_runs_both_modes_and_counts_contacts_only_when_rigid",
    "test_two_sweep_processes_on_one_folder_never_run_a_run_twice",
    "test_process_pool_gives_the_same_results_as_in_process",
    "test_run_ggc_example",
    "test_fcdfs_settles_on_a_lattice",
    "test_robots_sleep_once_settled",
    "test_deciding_in_chunks_changes_nothing",
    "test_sleep_changes_nothing_at_d_cover_1_where_movers_push_the_formation",
    "test_under_yield_holes_two_groups_meeting_head_on_park_no_one",
    "test_where_the_target_is_full_every_robot_of_every_group_ends_standing",
    "test_same_seed_same_run",
    "test_formation_controllers_wait_in_formation",
    "test_sigterm_stops_a_sweep_and_its_worker_processes",
    "test_small_world_is_covered_fully",
    "test_lattice_stop_still_covers_the_small_world",
    "test_shuffled_decision_order_changes_nothing_with_noise_and_message_loss_either",
    "test_text_l_world_is_valid_and_its_first_run_covers_the_target",
    "test_small_two_group_world_from_a_scattered_start_is_covered",
    "test_small_reproduction_writes_tables_plots_and_report",
    "test_another_groups_mover_with_priority_makes_a_mover_stop",
    "test_dask_cluster_runs_the_same_sweep",
})
"""Tests left out of the fast subset (``-m "not slow"``), by function name (every parameter)."""


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """Mark the tests of SLOW_TESTS ``slow``."""
    for item in items:
        if getattr(item, "originalname", item.name) in SLOW_TESTS:
            item.add_marker(pytest.mark.slow)


def square_world(size: float = 40.0, spawn: float = 20.0, gap: float = 10.0,
                 beacon: bool = True, margin: float = 10.0) -> World:
    """A square target [0, size]^2 with a spawn square below it."""
    data = {
        "name": "square",
        "target": {"outline": [[0, 0], [size, 0], [size, size], [0, size]]},
        "spawn": [{"outline": [[0, -gap - spawn], [spawn, -gap - spawn], [spawn, -gap],
                               [0, -gap]]}],
        "arena": {"margin": margin},
    }
    if beacon:
        data["beacon"] = {"position": [size / 2, size / 2]}
    return world_from_dict(data)


def small_world(width: float = 30.0, height: float = 24.0) -> World:
    """A small rectangular target with a spawn band below it and a beacon inside."""
    return world_from_dict({
        "name": "small",
        "target": {"outline": [[0, 0], [width, 0], [width, height], [0, height]]},
        "spawn": [{"outline": [[-5, -30], [width + 5, -30], [width + 5, -12], [-5, -12]]}],
        "beacon": {"position": [width / 2, height / 2]},
        "arena": {"margin": 15.0},
    })


@pytest.fixture
def square() -> World:
    return square_world()
