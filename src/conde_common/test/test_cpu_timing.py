"""CpuTiming: the timing line the benchmarks parse, and when it is logged."""
import re

from conde_common.cpu_timing import CpuTiming

TIMING_LINE = re.compile(r"^(conde_\w+): timing: (\d+) frames, mean (\d+\.\d\d) ms, max (\d+\.\d\d) ms CPU per frame$")


def test_line_format_and_values():
    lines = []
    timing = CpuTiming("conde_test", log_period_s=1e9, log=lines.append)
    for cpu_s in (0.001, 0.003, 0.002):
        timing.add(cpu_s)
    assert lines == []  # not due yet
    m = TIMING_LINE.match(timing.line())
    assert m and m.groups() == ("conde_test", "3", "2.00", "3.00")


def test_logged_when_due():
    lines = []
    timing = CpuTiming("conde_test", log_period_s=0.0, log=lines.append)
    timing.add(0.0005)
    assert lines == ["conde_test: timing: 1 frames, mean 0.50 ms, max 0.50 ms CPU per frame"]


def test_no_frames():
    assert CpuTiming("conde_test", log=lambda line: None).line() == \
        "conde_test: timing: 0 frames, mean 0.00 ms, max 0.00 ms CPU per frame"
