"""Pure parts of benchmark_driving_stack: /proc/<pid>/stat CPU time and the one speed table.

No ROS here; the process plumbing (running autonomous_run, polling /proc) is in the script.
"""
import os
import re

# Nodes listed first, in this order, when present; any other node of the run follows by name.
NODE_ORDER = ("conde_sim", "robot_state_publisher", "signalling_panel_controller", "conde_semaphore",
              "conde_tracking", "conde_decision", "conde_control", "conde_referee")
OTHER_PREFIX = "(other) "
SIM_WALL_ROW = re.compile(r"\| simulated / wall time \| ([\d.]+) s / ([\d.]+) s \(real-time factor ([\d.]+)\) \|")
TIMEOUTS_ROW = re.compile(r"\| lock-step \| yes, (\d+) frames timed out \|")
TIMING_LINE = re.compile(r"\b(conde_\w+): timing: (\d+) frames, mean (\d+\.\d+) ms, max (\d+\.\d+) ms CPU per frame")


def process_row_name(args):
    """Row of a process from its command-line arguments: the node name of a ROS node (argument
    __name:=<node>), else "(other) <program>" (the script an interpreter runs, else the executable),
    "" for an empty command line (a zombie)."""
    args = [a for a in args if a]
    if not args:
        return ""
    for arg in args:
        if arg.startswith("__name:="):
            return arg[len("__name:="):]
    program = args[1] if len(args) > 1 and os.path.basename(args[0]).startswith("python") else args[0]
    return OTHER_PREFIX + os.path.basename(program)


def stat_cpu_s(stat_text, clock_ticks_per_s):
    """utime + stime [s] from the text of /proc/<pid>/stat (fields 14 and 15, counted from 1;
    the command name in parentheses may hold spaces, so fields are counted after its last ')')."""
    fields = stat_text.rsplit(")", 1)[1].split()  # fields[0] is field 3 (state)
    return (int(fields[11]) + int(fields[12])) / float(clock_ticks_per_s)


def parse_summary(text):
    """{sim_s, wall_s, real_time_factor, timeouts} from autonomous_run's Markdown summary; None
    where the row is missing."""
    sim_wall = SIM_WALL_ROW.search(text)
    timeouts = TIMEOUTS_ROW.search(text)
    return {
        "sim_s": float(sim_wall.group(1)) if sim_wall else None,
        "wall_s": float(sim_wall.group(2)) if sim_wall else None,
        "real_time_factor": float(sim_wall.group(3)) if sim_wall else None,
        "timeouts": int(timeouts.group(1)) if timeouts else None,
    }


def parse_timing(log_text):
    """{node: CPU seconds of its main callback} from the last line "<node>: timing: <N> frames, mean
    <A> ms, ..." of each node in a roslaunch log (the nodes' own time.thread_time of the callback)."""
    timing = {}
    for match in TIMING_LINE.finditer(log_text):
        timing[match.group(1)] = int(match.group(2)) * float(match.group(3)) * 1e-3
    return timing


def ordered_nodes(runs):
    """Rows of the table: the known nodes in NODE_ORDER, then the others by name."""
    seen = set()
    for run in runs.values():
        seen.update(run["cpu_s"])
    others = sorted(n for n in seen if n.startswith(OTHER_PREFIX))
    known = [n for n in NODE_ORDER if n in seen]
    return known + sorted(seen - set(known) - set(others)) + others


def _cpu_cell(cpu_s, sim_s):
    if cpu_s is None or not sim_s:
        return "-"
    return f"{1000.0 * cpu_s / sim_s:.0f}"


def speed_table(runs):
    """Markdown table: per node and engine the CPU milliseconds per simulated second; then the
    run's total CPU per simulated second of the ROS nodes and with the other processes (start-up and
    autonomous_run's evaluation included), the best real-time factor 2 cores allow at the nodes' CPU
    cost (2 / nodes' total), simulated/wall time, real-time factor, frames timed out and load average.

    Where a run has "callback_s" (parse_timing), rows with the CPU of those nodes' callbacks alone
    follow the nodes (the difference to the node's row is its rospy plumbing).

    runs: {engine: {"cpu_s": {node: CPU seconds}, "summary": parse_summary(...), ["callback_s": {node: s},]
                    "load_avg": (mean, max) of the 1-minute load average during the run or None,
                    "exit_status": int}}
    """
    engines = list(runs)
    lines = ["| node | " + " | ".join(f"{e}: CPU [ms per simulated s]" for e in engines) + " |",
             "|---|" + "---|" * len(engines)]
    for node in ordered_nodes(runs):
        cells = [_cpu_cell(runs[e]["cpu_s"].get(node), runs[e]["summary"]["sim_s"]) for e in engines]
        lines.append(f"| {node} | " + " | ".join(cells) + " |")

    callback_nodes = [n for n in NODE_ORDER if any(n in runs[e].get("callback_s", {}) for e in engines)]
    for node in callback_nodes:
        cells = [_cpu_cell(runs[e].get("callback_s", {}).get(node), runs[e]["summary"]["sim_s"]) for e in engines]
        lines.append(f"| {node}: its callback alone (its timing line) | " + " | ".join(cells) + " |")

    def row(label, value_of):
        lines.append(f"| {label} | " + " | ".join(value_of(runs[e]) for e in engines) + " |")

    def total_s(run):
        return sum(run["cpu_s"].values())

    def sim(run):
        return run["summary"]["sim_s"]

    def nodes_s(run):
        return sum(v for k, v in run["cpu_s"].items() if not k.startswith(OTHER_PREFIX))

    row("**total of the ROS nodes [ms per simulated s]**", lambda r: _cpu_cell(nodes_s(r), sim(r)))
    row("total with the other processes [ms per simulated s]", lambda r: _cpu_cell(total_s(r), sim(r)))
    row("best RTF on 2 cores at the nodes' CPU (2 / nodes' total)",
        lambda r: f"{2.0 * sim(r) / nodes_s(r):.2f}" if sim(r) and nodes_s(r) else "-")
    row("simulated / wall time [s]",
        lambda r: f"{sim(r):.1f} / {r['summary']['wall_s']:.1f}" if sim(r) is not None else "-")
    row("real-time factor (wall time from launch)",
        lambda r: f"{r['summary']['real_time_factor']:.2f}" if r["summary"]["real_time_factor"] is not None else "-")
    row("lock-step frames timed out",
        lambda r: str(r["summary"]["timeouts"]) if r["summary"]["timeouts"] is not None else "-")
    row("load average (1 min) during the run: mean / max",
        lambda r: f"{r['load_avg'][0]:.1f} / {r['load_avg'][1]:.1f}" if r["load_avg"] else "-")
    row("autonomous_run exit status", lambda r: str(r["exit_status"]))
    return "\n".join(lines)
