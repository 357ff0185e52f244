"""Shared fixtures: generated garments and the real ones in ../shared (skipped when absent)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("PTAILOR_SHARED", ROOT.parent / "shared"))
GARMENTS = SHARED / "garments"

#: real garments: path relative to shared/garments, pattern units
REAL = {
    "tee6": ("gpg_tee6/tee6_sim.obj", "cm"),
    "tshirt": ("diffavatar/tshirt.obj", "auto"),
    "longsleeve": ("diffavatar/longsleeve_initial.obj", "auto"),
    "dress": ("diffavatar/dress_initial.obj", "auto"),
}


def real_path(key: str) -> Path:
    """Path of a shared garment, skipping the test when it is absent."""
    p = GARMENTS / REAL[key][0]
    if not p.is_file():
        pytest.skip(f"{p} not available (../shared is absent)")
    return p


@pytest.fixture(params=sorted(REAL))
def real_garment(request):
    """(key, LoadedGarment) for each real garment."""
    from ptailor.formats.garment import load_garment

    p = real_path(request.param)
    return request.param, load_garment(p, pattern_units=REAL[request.param][1])


# The quick loop: `pytest -m "not slow"` runs in under a minute; plain `pytest` (what CI runs)
# runs everything (measured on a quiet 2-core machine: 707 tests in 18 s, all 981 in 132 s).
# The slow tests are named here, by module and function (all of a function's parameters), so
# the test files stay as they are. Measured with `pytest --durations=0`: every test function
# that took 0.6 s or more in all (its parameters together) on a loaded 2-core machine.
# Re-measure when adding a test that runs the CLI on real garments, a batch or a fuzzing
# campaign, and add it here.
SLOW: dict[str, frozenset[str]] = {
    "test_spec": frozenset(
        {
            "test_identity_gives_the_real_spec_back",
            "test_identity_gives_the_generated_spec_back",
            "test_tee6_uniform_scale",
            "test_tee6_one_sleeve_wider",
            "test_tee6_shorten_moves_only_the_hem",
            "test_written_curves_lie_on_the_adjusted_outline",
            "test_a_turned_drape_gives_the_same_specification",
            "test_an_obliquely_moved_generated_drape_gives_the_same_specification",
            "test_shirt_shorten_moves_only_the_hems",
            "test_batch_finds_each_specification_beside_its_garment",
            "test_manifest_spec_column",
            "test_batch_max_spec_fit_gate",
        }
    ),
    "test_spec_curves": frozenset({"test_one_reparametrization_round_refits_at_the_feet"}),
    "test_inspect_spec": frozenset(
        {
            "test_tee6_spec_panels_are_the_mesh_panels_named_like_them",
            "test_tee6_every_stitch_has_a_seam_and_its_lengths",
            "test_tee6_text_lists_the_panels_and_stitches",
            "test_shirt_panels_and_stitches",
            "test_shirt_panel_matching_agrees_with_garmentcodes_segmentation",
            "test_shirt_stitches_lie_on_their_seams_in_garmentcodes_segmentation",
            "test_json_has_the_spec_section",
            "test_units_convert_the_lengths",
            "test_a_spec_of_another_garment_exits_2_naming_the_file",
            "test_a_panel_of_another_shape_exits_2_naming_the_file_and_the_panel",
        }
    ),
    "test_obj_scan": frozenset({"test_scan_matches_record_parser_on_mutants"}),
    "test_outputs_imports": frozenset({"test_writing_all_formats_does_not_import_matplotlib"}),
    "test_bad_dxf": frozenset(
        {
            "test_many_shuffled_boundary_parts_chain_in_linear_time",
            "test_shared_fixture_with_an_extreme_coordinate",
        }
    ),
    "test_bad_edits": frozenset(
        {
            "test_a_large_max_iter_on_a_former_limit_cycle_converges",
            "test_garment_errors_through_the_cli_name_the_file",
            "test_scale_around_tiny_factor_warns_naming_the_panels",
        }
    ),
    "test_bad_obj": frozenset(
        {
            "test_a_flat_drape_ends_with_a_warning_that_says_why",
            "test_bom_and_crlf_sleeve_give_the_same_garment",
            "test_corpus_adjust_and_inspect",
            "test_duplicated_faces_all_formats",
            "test_unreferenced_vt_before_the_used_ones",
        }
    ),
    "test_batch": frozenset(
        {
            "test_a_garment_that_kills_its_worker_fails_alone",
            "test_batch_isolates_a_broken_garment_and_records_in_input_order",
            "test_dxf_patterns_with_their_drapes_in_a_folder",
            "test_globs_folders_stdin_and_shared_stems",
            "test_quality_gates",
            "test_rerun_skips_unchanged_and_redoes_changed",
            "test_same_bytes_from_one_two_workers_and_dask",
            "test_sigint_leaves_complete_folders_and_a_rerun_finishes",
            "test_worker_pool_isolates_failures_quietly",
        }
    ),
    "test_manifest": frozenset(
        {
            "test_a_dxf_row_with_its_own_drape_size_and_unit",
            "test_a_missing_column_or_empty_cell_takes_the_command_line",
            "test_csv_and_json_lines_manifests_give_what_separate_runs_give",
            "test_real_garments_with_their_own_units_in_one_manifest",
            "test_rerun_skips_every_row_and_a_changed_unit_redoes_that_garment_only",
        }
    ),
    "test_cli": frozenset(
        {
            "test_adjust_writes_outputs_and_can_adjust_its_own_output",
            "test_demo",
            "test_drape_from_second_file",
            "test_method_uniform_override_and_json",
            "test_outputs_are_deterministic",
            "test_recipe_from_stdin",
        }
    ),
    "test_dxf": frozenset(
        {
            "test_inspect_real_tank_sizes",
            "test_real_clo3d",
            "test_real_files_round_trip",
            "test_real_tank_gerber",
        }
    ),
    "test_dxf_roundtrip": frozenset(
        {
            "test_a_cut_splitting_the_generated_skirts_front_writes_both_parts",
            "test_a_drape_whose_vt_is_in_another_unit_than_the_dxf",
            "test_a_dxf_naming_no_unit_takes_it_from_the_drape",
            "test_a_fold_piece_cut_by_an_edit_is_the_new_panels_half",
            "test_a_fold_piece_matches_its_unfolded_panel_and_is_written_back_as_a_fold_piece",
            "test_a_fold_piece_that_matches_nothing_is_an_error_naming_the_fold",
            "test_a_left_right_pair_is_written_as_one_cut_as_drawn_and_one_mirrored",
            "test_a_v_cut_that_splits_tee6s_front_keeps_every_panel_as_a_dxf_piece",
            "test_a_v_cut_through_a_dxf_piece_writes_both_parts",
            "test_implausible_piece_sizes_are_a_warning",
            "test_shared_dxfs_round_trip_with_every_mark_and_quantity",
            "test_the_demos_dxf_round_trips_with_its_drape",
            "test_the_gerber_tanks_fold_pieces_round_trip_with_a_drape_of_their_wholes",
            "test_the_readmes_dxf_example_runs_on_the_demos_own_output",
            "test_turn_back_lines_follow_a_uniform_scale_and_a_cut_keeps_those_of_its_part",
            "test_turn_back_lines_outside_the_cut_line_survive_identity",
        }
    ),
    "test_resolution": frozenset(
        {
            "test_a_production_resolution_tee_loosened_converges_with_its_seams_closed",
            "test_a_production_resolution_tshirt_gathered_at_both_armholes_converges",
            "test_one_adjustment_agrees_at_1x_and_4x",
            "test_the_dress_skirt_widened_converges_near_its_optimum",
            "test_the_flatten_of_one_edit_agrees_at_1x_and_4x",
        }
    ),
    "test_ease": frozenset(
        {
            "test_a_cap_that_stops_the_solver_is_a_warning_naming_the_panel",
            "test_a_tube_widened_on_one_side_keeps_its_side_seams",
            "test_anderson_converges_in_fewer_iterations_to_the_same_pattern",
            "test_real_sleeve_widened_keeps_every_seam",
            "test_report_gives_each_seams_ratio_target_and_mismatch",
            "test_seam_ease_reads_ratios_and_gathers_from_the_pattern",
        }
    ),
    "test_extend": frozenset(
        {
            "test_cone_skirt_hem_moves_5_outward_waist_and_side_seams_kept",
            "test_dress_neckline_extended_by_8_in_the_pattern",
            "test_extend_after_a_scale_follows_the_scaled_cuff",
            "test_extending_into_a_hole_further_than_it_is_wide_is_refused",
            "test_lantern_cuff_strip_follows_the_cuff_intrinsic_scale",
            "test_output_can_be_adjusted_again",
            "test_real_hem_extended_by_5_in_the_output_pattern",
            "test_tee6_hem_extend_is_valid_and_keeps_seams_equal",
            "test_tee6_hem_extended_keeps_its_seams_and_the_drape_measure_does_not_the_hem",
            "test_tee_cuff_extended_by_5_cm_exits_0",
        }
    ),
    "test_fuzz_dxf": frozenset(
        {
            "test_adjust_mutated_dxf_fails_closed",
            "test_inspect_mutated_dxf_fails_closed",
            "test_mutate_is_deterministic_and_changes_the_file",
        }
    ),
    "test_fuzz_edits": frozenset({"test_extreme_edits_exit_cleanly_and_never_write_nan"}),
    "test_fuzz_obj": frozenset(
        {
            "test_adjust_and_inspect_keep_the_contract",
            "test_one_extreme_everywhere",
            "test_reader_fails_closed",
        }
    ),
    "test_fuzz_recipe": frozenset(
        {
            "test_mutated_recipes_keep_the_contract",
            "test_random_yaml_documents_keep_the_contract",
        }
    ),
    "test_intake": frozenset(
        {
            "test_adjust_report_has_intake",
            "test_duplicate_and_zero_area_faces_are_dropped_and_counted",
            "test_dxf_pattern_reports_where_its_units_came_from",
            "test_generated_unwelded_every_vertex_welds_back",
            "test_generated_weld_off_keeps_pieces_apart_and_warns",
            "test_real_garments_pass_the_unit_check",
            "test_real_unwelded_gives_the_same_seams_openings_and_pattern",
            "test_tee6_unit_mistake",
            "test_weld_distance_and_batch_stamp",
        }
    ),
    "test_loosen": frozenset(
        {
            "test_cylinder_pattern_width_grows_by_2_pi_d_over_s",
            "test_lantern_middle_ring_grows_by_by_and_the_ends_stay",
            "test_real_tightening_sleeves_past_their_radius_names_them",
            "test_real_torso_loosen_2cm_widens_the_pattern_by_2_pi_d_over_s",
            "test_real_torso_loosen_cli_exits_0_without_flips",
            "test_real_torso_offset_adds_2_pi_d_of_girth",
            "test_silhouette_tightens_the_skirt_onto_the_sketch",
            "test_tee6_loosen_all_is_valid",
            "test_wrinkles_ride_along_and_the_girth_grows_by_2_pi_d",
        }
    ),
    "test_pieces": frozenset(  # was test_marks
        {"test_moved_and_flipped_pieces_match_by_shape_with_the_right_rigid_map"}
    ),
    "test_method": frozenset(
        {
            "test_axis_auto_finds_tube_axis",
            "test_identity_returns_pattern",
            "test_lantern_paper_intrinsic_is_slightly_off",
            "test_partial_region_follows_smoothly_and_keeps_seams_closed",
            "test_seam_ease_keeps_the_invariants",
            "test_uniform_scale_scales_every_panel",
        }
    ),
    "test_names": frozenset(
        {
            "test_cli_adjust_by_names_reports_named_seams",
            "test_dress_seam_names_are_unique_and_find_the_waist",
            "test_mirror_image_swaps_the_seam_names",
            "test_one_catalogue_recipe_runs_on_every_shared_garment",
            "test_real_garments_get_geometric_names",
            "test_tee6_symmetric_recipe_by_names_grows_both_sleeves",
            "test_tshirt_recipe_scales_the_left_sleeve_by_its_name",
        }
    ),
    "test_options": frozenset(
        {
            "test_axes_from_recipe_or_command_line",
            "test_body_option",
        }
    ),
    "test_output_safety": frozenset(
        {
            "test_a_garment_stuck_past_its_timeout_has_its_worker_killed",
            "test_a_signal_while_writing_leaves_no_staging_and_the_old_output",
            "test_batch_timeout_fails_the_garment_and_writes_nothing",
            "test_kill_9_of_a_batch_ends_its_workers_and_keeps_the_records_it_had",
            "test_sigterm_at_random_times_never_leaves_staging",
        }
    ),
    "test_pattern_io": frozenset(
        {
            "test_a_moved_piece_is_matched_by_shape_and_written_where_the_file_had_it",
            "test_a_piece_cut_twice_matches_both_panels_and_is_written_as_two",
            "test_a_uniform_scale_scales_every_mark_and_keeps_the_grain_direction",
            "test_adjust_writes_every_format_by_default",
            "test_cut_lines_with_a_seam_allowance_match_the_mesh_of_the_sew_line",
            "test_extend_drops_the_notches_it_leaves_inside_the_piece",
            "test_identity_on_a_dxf_and_its_drape_gives_back_outlines_and_marks",
            "test_outputs_are_byte_identical_across_runs",
            "test_seam_allowance_offsets_the_cut_line_and_keeps_the_sew_line",
            "test_shorten_drops_the_marks_it_cuts_away_and_outlines_the_new_hem",
            "test_units_override_for_a_metric_file",
        }
    ),
    "test_real": frozenset(
        {
            "test_identity_returns_every_vt",
            "test_rigid_motion_and_uniform_scale",
            "test_tee6_one_sleeve_wider_body_follows",
            "test_tee6_seams_ease_matches_seam_lengths",
            "test_tshirt_mirrored_panel_scales_and_keeps_orientation",
        }
    ),
    "test_recipes": frozenset(
        {"test_recipe_validates_and_runs", "test_recipe_runs_on_the_shared_garments_it_names"}
    ),
    "test_scale_seam": frozenset(
        {
            "test_around_widens_the_sleeve_bottom_keeps_the_top_and_the_cuff",
            "test_body_axis_drives_auto_axes",
            "test_tee6_armhole_seam_stays_valid",
            "test_the_shared_long_sleeves_armhole_by_name_symmetric_too",
        }
    ),
    "test_shell": frozenset(
        {
            "test_adjust_catalogue_finds_garments_and_writes_a_csv_summary",
            "test_adjust_catalogue_follows_symbolic_links",
            "test_adjust_catalogue_writes_a_manifest_that_batch_takes",
            "test_adjust_each_runs_every_garment_and_reports_failures",
            "test_adjust_parallel_falls_back_to_xargs_without_gnu_parallel",
        }
    ),
    "test_shorten": frozenset(
        {
            "test_dress_hem_edits_are_valid_and_readjustable",
            "test_generated_hems_move_exactly_5_in_the_output_pattern",
            "test_real_hem_shortened_by_5_in_the_output_pattern",
            "test_shorten_hem_on_real_garments",
            "test_tee6_hem_shortened_by_5_on_the_drape_is_uneven_in_the_pattern",
        }
    ),
    "test_surgery": frozenset(
        {
            "test_cut_errors",
            "test_cut_output_can_be_adjusted_again",
            "test_plane_cut_on_real_garments",
        }
    ),
    "test_symmetry": frozenset(
        {
            "test_symmetric_recipe_mirrors_a_one_sided_step",
            "test_symmetric_scale_seam_renames_seam_part_and_fixed_loop",
            "test_tee6_one_sided_sleeve_scale_keeps_the_right_sleeve",
            "test_tee6_symmetric_sleeve_scale_changes_both_sleeves_alike",
        }
    ),
    "test_proxy": frozenset({"test_a_production_resolution_tee_is_simulated_on_8000_triangles"}),
    "test_tseam": frozenset({"test_cli_inspect_and_adjust_on_a_tseam"}),
    "test_walk": frozenset({"test_demo_a_dxf_adjustment_and_a_batch_walk_down"}),
    "test_validate": frozenset({"test_example_recipes_pass_the_schema_and_the_rules"}),
    "test_verify_cli": frozenset(
        {"test_real_engine_adjust_and_verify", "test_tee6_on_its_own_body_settles_within_minutes"}
    ),
    "test_verify_engine": frozenset(
        {
            "test_a_tight_tube_is_stretched_over_the_cylinder",
            "test_a_tube_at_rest_barely_moves_and_says_nothing",
        }
    ),
    "test_verify": frozenset(
        {
            "test_lantern_widened_on_an_arm_redrapes_like_the_edit",
            "test_lantern_baseline_cuff_is_held_by_the_arm",
            "test_the_lantern_simulated_on_a_decimated_mesh_gives_the_same_verdict",
            "test_verify_png_is_deterministic",
        }
    ),
}


def pytest_collection_modifyitems(config, items):
    """Mark the tests named in :data:`SLOW` with ``slow``."""
    for item in items:
        module = item.path.stem if hasattr(item, "path") else Path(str(item.fspath)).stem
        name = getattr(item, "originalname", None) or item.name.split("[")[0]
        if name in SLOW.get(module, ()):
            item.add_marker(pytest.mark.slow)


# Property-based fuzzing (Hypothesis): short and seeded in CI, longer on demand:
#   PTAILOR_FUZZ=long python -m pytest tests/test_fuzz_*.py
try:
    from hypothesis import HealthCheck, settings

    _fuzz_common = {
        "deadline": None,
        "derandomize": True,  # seeded: the same cases every run
        "suppress_health_check": [HealthCheck.too_slow, HealthCheck.data_too_large],
        "database": None,
    }
    settings.register_profile("ci", max_examples=60, **_fuzz_common)
    settings.register_profile("long", max_examples=2000, **_fuzz_common)
    settings.load_profile(os.environ.get("PTAILOR_FUZZ", "ci"))
except ImportError:  # hypothesis comes with the test extra
    pass


def pytest_addoption(parser):
    """``--refresh-golden``: rewrite tests/golden/*.npz from this run (tests/test_golden.py)."""
    parser.addoption(
        "--refresh-golden",
        action="store_true",
        help="rewrite the golden expectations of tests/test_golden.py from this run",
    )
