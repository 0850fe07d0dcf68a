//! On-target tests under QEMU (`cargo test --release`, see README), run by knurling's
//! `defmt-test`: the kernel in f32 on the Cortex-M4F against f64 values computed on the host
//! at build time (PHAK here, gait2392 and a subject model sent to the hub in
//! `on_target/gait2392.rs`), the UART receive ring's block read (`on_target/rx_ring.rs`), and
//! every scenario check of `qgait-hub-checks` (sample assembly, error counting,
//! configuration), each its own test.
//!
//! defmt-test prints ``(k/N) running `name`...`` before each test and exits with status 0 after
//! the last; a failed test panics, and the firmware's panic handler exits with 101. The runner
//! (`cargo xtask qemu-run`) counts those lines into the summary `N passed, M failed`.

#![no_std]
#![no_main]

// The panic and HardFault handlers, and the board's defmt logger and semihosting exit.
use qgait_firmware as _;

#[path = "on_target/gait2392.rs"]
mod gait2392;
#[path = "on_target/kernel.rs"]
mod kernel;
#[path = "on_target/rx_ring.rs"]
mod rx_ring;

/// The scenario checks of `qgait-hub-checks` run so far, so that the last test can tell that
/// each one ran exactly once (a check added to the list needs its own test below).
pub struct SharedChecks {
    runs: [u8; qgait_hub_checks::ALL.len()],
}

impl SharedChecks {
    /// Runs the check named `name` of `qgait_hub_checks::ALL` and records that it ran.
    fn run(&mut self, name: &str) -> qgait_hub_checks::CheckResult {
        let Some(k) = qgait_hub_checks::ALL.iter().position(|(n, _)| *n == name) else {
            defmt::panic!("no shared check named {=str}", name);
        };
        self.runs[k] += 1;
        (qgait_hub_checks::ALL[k].1)()
    }
}

#[defmt_test::tests]
mod tests {
    use qgait_hub_checks::{CheckResult, ALL};

    use super::{gait2392, kernel, rx_ring, SharedChecks};

    #[init]
    fn init() -> SharedChecks {
        SharedChecks {
            runs: [0; ALL.len()],
        }
    }

    #[test]
    fn kernel_f32_points_match_host_f64() {
        kernel::f32_points_match_host_f64();
    }

    #[test]
    fn kernel_f32_distances_match_host_f64() {
        kernel::f32_distances_match_host_f64();
    }

    #[test]
    fn kernel_cases_are_not_degenerate() {
        kernel::cases_are_not_degenerate();
    }

    #[test]
    fn sqrt_f32_is_correctly_rounded() {
        kernel::sqrt_f32_is_correctly_rounded();
    }

    #[test]
    fn gait2392_f32_points_match_host_f64() {
        gait2392::gait2392_f32_points_match_host_f64();
    }

    #[test]
    fn subject_model_on_the_hub_matches_host_f64() {
        gait2392::subject_model_on_the_hub_matches_host_f64();
    }

    #[test]
    fn rx_ring_block_read_wraps_around() {
        rx_ring::rx_ring_block_read_wraps_around();
    }

    #[test]
    fn rx_ring_errors_come_after_the_bytes_before_them() {
        rx_ring::rx_ring_errors_come_after_the_bytes_before_them();
    }

    #[test]
    fn clean_stream_gives_one_pose_per_sample(c: &mut SharedChecks) -> CheckResult {
        c.run("clean_stream_gives_one_pose_per_sample")
    }

    #[test]
    fn pose_matches_the_kernel(c: &mut SharedChecks) -> CheckResult {
        c.run("pose_matches_the_kernel")
    }

    #[test]
    fn velocities_follow_consecutive_poses(c: &mut SharedChecks) -> CheckResult {
        c.run("velocities_follow_consecutive_poses")
    }

    #[test]
    fn packets_reordered_within_the_window_still_complete(c: &mut SharedChecks) -> CheckResult {
        c.run("packets_reordered_within_the_window_still_complete")
    }

    #[test]
    fn late_and_duplicate_packets_are_counted_and_dropped(c: &mut SharedChecks) -> CheckResult {
        c.run("late_and_duplicate_packets_are_counted_and_dropped")
    }

    #[test]
    fn incomplete_sample_is_dropped_and_counted(c: &mut SharedChecks) -> CheckResult {
        c.run("incomplete_sample_is_dropped_and_counted")
    }

    #[test]
    fn hold_last_policy_sends_flagged_frames(c: &mut SharedChecks) -> CheckResult {
        c.run("hold_last_policy_sends_flagged_frames")
    }

    #[test]
    fn held_angle_out_of_range_is_flagged(c: &mut SharedChecks) -> CheckResult {
        c.run("held_angle_out_of_range_is_flagged")
    }

    #[test]
    fn corrupt_frames_are_counted_and_the_next_packet_is_processed(
        c: &mut SharedChecks,
    ) -> CheckResult {
        c.run("corrupt_frames_are_counted_and_the_next_packet_is_processed")
    }

    #[test]
    fn unknown_joint_and_version_are_counted(c: &mut SharedChecks) -> CheckResult {
        c.run("unknown_joint_and_version_are_counted")
    }

    #[test]
    fn angles_out_of_range_are_flagged_and_unusable_ones_dropped(
        c: &mut SharedChecks,
    ) -> CheckResult {
        c.run("angles_out_of_range_are_flagged_and_unusable_ones_dropped")
    }

    #[test]
    fn uart_overrun_is_counted(c: &mut SharedChecks) -> CheckResult {
        c.run("uart_overrun_is_counted")
    }

    #[test]
    fn config_switches_model_and_answers_status_request(c: &mut SharedChecks) -> CheckResult {
        c.run("config_switches_model_and_answers_status_request")
    }

    #[test]
    fn unusable_config_is_refused_and_counted(c: &mut SharedChecks) -> CheckResult {
        c.run("unusable_config_is_refused_and_counted")
    }

    #[test]
    fn status_request_keeps_open_samples(c: &mut SharedChecks) -> CheckResult {
        c.run("status_request_keeps_open_samples")
    }

    #[test]
    fn status_is_sent_periodically(c: &mut SharedChecks) -> CheckResult {
        c.run("status_is_sent_periodically")
    }

    #[test]
    fn gait2392_config_gives_frames_of_the_generic_model(c: &mut SharedChecks) -> CheckResult {
        c.run("gait2392_config_gives_frames_of_the_generic_model")
    }

    #[test]
    fn subject_model_switches_only_when_complete(c: &mut SharedChecks) -> CheckResult {
        c.run("subject_model_switches_only_when_complete")
    }

    #[test]
    fn invalid_subject_model_is_rejected_and_counted(c: &mut SharedChecks) -> CheckResult {
        c.run("invalid_subject_model_is_rejected_and_counted")
    }

    #[test]
    fn parts_of_another_upload_discard_the_held_ones(c: &mut SharedChecks) -> CheckResult {
        c.run("parts_of_another_upload_discard_the_held_ones")
    }

    #[test]
    fn chain_model_switches_only_when_complete(c: &mut SharedChecks) -> CheckResult {
        c.run("chain_model_switches_only_when_complete")
    }

    #[test]
    fn a_chains_knee_flexing_with_positive_angles_is_checked_in_its_range(
        c: &mut SharedChecks,
    ) -> CheckResult {
        c.run("a_chains_knee_flexing_with_positive_angles_is_checked_in_its_range")
    }

    #[test]
    fn random_bytes_never_stop_the_pipeline(c: &mut SharedChecks) -> CheckResult {
        c.run("random_bytes_never_stop_the_pipeline")
    }

    #[test]
    fn each_poll_reads_at_most_max_bytes_per_poll(c: &mut SharedChecks) -> CheckResult {
        c.run("each_poll_reads_at_most_max_bytes_per_poll")
    }

    #[test]
    fn frames_split_across_reads_and_polls_still_decode(c: &mut SharedChecks) -> CheckResult {
        c.run("frames_split_across_reads_and_polls_still_decode")
    }

    #[test]
    fn orientation_input_calibrates_then_sends_kernel_poses(c: &mut SharedChecks) -> CheckResult {
        c.run("orientation_input_calibrates_then_sends_kernel_poses")
    }

    #[test]
    fn orientation_failures_are_counted(c: &mut SharedChecks) -> CheckResult {
        c.run("orientation_failures_are_counted")
    }

    #[test]
    fn calibration_is_kept_across_model_and_input_switches(c: &mut SharedChecks) -> CheckResult {
        c.run("calibration_is_kept_across_model_and_input_switches")
    }

    #[test]
    fn incomplete_orientation_samples_follow_the_missing_policy(
        c: &mut SharedChecks,
    ) -> CheckResult {
        c.run("incomplete_orientation_samples_follow_the_missing_policy")
    }

    #[test]
    fn random_orientation_messages_never_stop_the_pipeline(c: &mut SharedChecks) -> CheckResult {
        c.run("random_orientation_messages_never_stop_the_pipeline")
    }

    /// Every check of `qgait_hub_checks::ALL` ran above, once.
    #[test]
    fn every_shared_check_ran_once(c: &mut SharedChecks) {
        for ((name, _), &runs) in ALL.iter().zip(&c.runs) {
            defmt::assert_eq!(runs, 1, "shared check {=str}", name);
        }
    }

    /// Last, so that the peak covers every test: the stack paint is in place below the
    /// deepest use so far, so `stack::peak` can measure.
    #[test]
    fn stack_paint_is_measurable() {
        kernel::stack_paint_is_measurable();
    }
}
