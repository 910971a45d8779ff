"""stack_benchmark: /proc stat parsing, summary parsing and the speed table of benchmark_driving_stack."""
from conde_eval import stack_benchmark

SUMMARY = """| result | value |
|---|---|
| simulated / wall time | 30.0 s / 15.0 s (real-time factor 2.00) |
| lock-step | yes, 2 frames timed out |
"""
LOG = """[INFO] [1.0, 10.0]: conde_tracking: timing: 10 frames, mean 9.00 ms, max 12.00 ms CPU per frame
[INFO] [2.0, 30.0]: conde_tracking: timing: 600 frames, mean 2.50 ms, max 9.00 ms CPU per frame
"""


def test_parse_timing_keeps_each_nodes_last_line_as_cpu_seconds():
    assert stack_benchmark.parse_timing(LOG) == {"conde_tracking": 1.5}


def test_stat_cpu_s_counts_fields_after_a_command_name_with_spaces_and_parentheses():
    # pid (comm) state ppid pgrp session tty tpgid flags minflt cminflt majflt cmajflt utime stime ...
    text = "4242 (odd (name) x) S 1 2 3 4 5 6 7 8 9 10 250 50 77 88 20 0 1 0\n"
    assert stack_benchmark.stat_cpu_s(text, 100) == 3.0


def test_parse_summary_reads_times_and_timeouts_and_marks_missing_rows():
    assert stack_benchmark.parse_summary(SUMMARY) == {
        "sim_s": 30.0, "wall_s": 15.0, "real_time_factor": 2.0, "timeouts": 2}
    assert stack_benchmark.parse_summary("") == {
        "sim_s": None, "wall_s": None, "real_time_factor": None, "timeouts": None}


def test_speed_table_puts_engines_side_by_side_with_totals_and_best_rtf():
    summary = stack_benchmark.parse_summary(SUMMARY)
    runs = {
        "ode": {"cpu_s": {"conde_tracking": 3.0, "conde_sim": 9.0, "(other) roslaunch": 3.0},
                "summary": summary, "load_avg": (9.5, 11.25), "exit_status": 1,
                "callback_s": stack_benchmark.parse_timing(LOG)},
        "bullet": {"cpu_s": {"conde_sim": 12.0, "zeta_node": 0.3},
                   "summary": stack_benchmark.parse_summary(""), "load_avg": None, "exit_status": 0},
    }
    lines = stack_benchmark.speed_table(runs).splitlines()
    assert lines[0] == "| node | ode: CPU [ms per simulated s] | bullet: CPU [ms per simulated s] |"
    rows = {line.split(" | ")[0][2:]: line.split(" | ")[1:] for line in lines[2:]}
    # known nodes first in the fixed order, then other nodes by name, then the other programs
    names = [line.split(" | ")[0][2:] for line in lines[2:6]]
    assert names == ["conde_sim", "conde_tracking", "zeta_node", "(other) roslaunch"]
    assert rows["conde_sim"] == ["300", "- |"]  # bullet has no simulated time: no per-second figure
    assert rows["conde_tracking"] == ["100", "- |"]
    assert rows["zeta_node"] == ["-", "- |"]
    assert rows["conde_tracking: its callback alone (its timing line)"] == ["50", "- |"]
    assert "conde_semaphore: its callback alone (its timing line)" not in rows
    assert rows["**total of the ROS nodes [ms per simulated s]**"] == ["400", "- |"]
    assert rows["total with the other processes [ms per simulated s]"] == ["500", "- |"]
    assert rows["best RTF on 2 cores at the nodes' CPU (2 / nodes' total)"] == ["5.00", "- |"]
    assert rows["simulated / wall time [s]"] == ["30.0 / 15.0", "- |"]
    assert rows["real-time factor (wall time from launch)"] == ["2.00", "- |"]
    assert rows["lock-step frames timed out"] == ["2", "- |"]
    assert rows["load average (1 min) during the run: mean / max"] == ["9.5 / 11.2", "- |"]
    assert rows["autonomous_run exit status"] == ["1", "0 |"]


def test_process_row_name_names_nodes_scripts_and_programs():
    assert stack_benchmark.process_row_name(
        ["/usr/bin/python3", "/x/conde_tracking", "__name:=conde_tracking", "__log:=/l", ""]) == "conde_tracking"
    assert stack_benchmark.process_row_name(["/usr/bin/python3", "/usr/bin/roslaunch", "-p", "1"]) == \
        "(other) roslaunch"
    assert stack_benchmark.process_row_name(["/opt/bin/rosmaster", "--core"]) == "(other) rosmaster"
    assert stack_benchmark.process_row_name([""]) == ""
