"""The seed's walking and turning campaign: trial specs, running a sequence of trials in a fresh
simulation (its own roslaunch of nao.launch on a private port, then walk_trial), and the
statistics over repeats. ROS is used only through the two commands' processes."""

import json
import math
import os
import signal
import socket
import statistics
import subprocess
import time
from dataclasses import dataclass

# The seed paper's campaign: straight walks at three speeds, turns both ways (angles in degrees,
# positive counter-clockwise).
WALK_DISTANCES_M = (0.5, 1.0, 3.0)
WALK_FRACTIONS = (0.4, 0.8, 1.0)
TURNS_DEG = (90.0, 360.0, -180.0, -270.0)
TURN_FRACTION = 1.0


@dataclass(frozen=True)
class Spec:
    kind: str              # 'walk' | 'turn'
    distance_m: float
    angle_rad: float
    speed_fraction: float
    goal: float            # [m] or [deg]


def parse_spec(text):
    """'walk:<m>:<fraction>' or 'turn:<deg>:<fraction>' -> Spec; ValueError naming the text."""
    parts = text.split(':')
    try:
        if len(parts) != 3 or parts[0] not in ('walk', 'turn'):
            raise ValueError
        value, fraction = float(parts[1]), float(parts[2])
    except ValueError:
        raise ValueError("bad trial spec '%s': expected walk:<distance m>:<speed fraction> or "
                         "turn:<angle deg>:<speed fraction>" % text)
    if parts[0] == 'walk':
        return Spec('walk', value, 0.0, fraction, value)
    return Spec('turn', 0.0, math.radians(value), fraction, value)


def campaign_specs(quick=False):
    """The campaign's spec strings; quick: the shortest walk and turn at each setting."""
    distances = WALK_DISTANCES_M[:1] if quick else WALK_DISTANCES_M
    turns = TURNS_DEG[:1] + TURNS_DEG[2:3] if quick else TURNS_DEG
    return (['walk:%g:%g' % (d, f) for d in distances for f in WALK_FRACTIONS]
            + ['turn:%g:%g' % (a, TURN_FRACTION) for a in turns])


def _free_port():
    with socket.socket() as s:
        s.bind(('127.0.0.1', 0))
        return s.getsockname()[1]


def _stop(process):
    try:
        os.killpg(process.pid, signal.SIGINT)
        process.wait(timeout=30)
    except ProcessLookupError:
        pass
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        process.wait()


def run_in_fresh_simulation(engine, command, log_path=None, timeout_s=1800.0, on_record=None):
    """Starts nao.launch with nao_walk, paused, on `engine` with its own master on a free port,
    runs `command` (argv) against it and returns the JSON records (lines starting with '{') it
    printed, calling `on_record(record)` as each comes. The simulation is stopped at the end."""
    port = _free_port()
    env = dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:%d' % port, PATH='/usr/bin:' + os.environ['PATH'])
    log = open(log_path, 'a') if log_path else subprocess.DEVNULL
    launch = subprocess.Popen(
        ['roslaunch', '-p', str(port), 'conde_bringup', 'nao.launch', 'controllers:=trajectory', 'walk:=true',
         'walk_ready_time:=0.2', 'cameras:=false', 'real_time_factor:=0', 'paused:=true',
         'physics_engine:=' + engine], env=env, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
    records = []
    try:
        run = subprocess.Popen(command, env=env, text=True, stdout=subprocess.PIPE, stderr=log)
        deadline = time.monotonic() + timeout_s
        for line in run.stdout:
            if line.startswith('{'):
                records.append(json.loads(line))
                if on_record:
                    on_record(records[-1])
            if time.monotonic() > deadline:
                run.kill()
        status = run.wait()
    finally:
        _stop(launch)
        if log_path:
            log.close()
    if status != 0 and not records:
        where = ', see ' + log_path if log_path else ''
        raise RuntimeError('%s on %s failed (exit %d)%s' % (' '.join(command[:3]), engine, status, where))
    return records


def run_sequence(engine, specs, log_path=None, timeout_s=1800.0, on_trial=None):
    """Runs `specs` (strings) one after the other in a fresh simulation on `engine`; returns the
    list of trial dicts (shorter than specs if the robot fell: the trial with the fall is last).
    `on_trial(trial)` is called as each trial ends."""
    return run_in_fresh_simulation(engine, ['rosrun', 'conde_humanoid', 'walk_trial'] + list(specs), log_path,
                                   timeout_s, on_trial)


def run_repeats(engine, specs, repeats, progress=print, log_path=None):
    """{spec: [trial per repeat]}; a sequence cut by a fall goes on in a fresh simulation.
    `progress(line)` gets one line per trial as it ends."""
    results = {s: [] for s in specs}
    for r in range(repeats):
        def report(trial, r=r):
            progress('%s repeat %d/%d %-14s x %+.3f m y %+.3f m turned %+7.1f deg%s (sim %.1f s, wall %.1f s)'
                     % (engine, r + 1, repeats, trial['spec'], trial['x_m'], trial['y_m'],
                        math.degrees(trial['turned_rad']), ' FELL' if trial['fell'] else '',
                        trial['sim_s'], trial['wall_s']))

        todo = list(specs)
        while todo:
            trials = run_sequence(engine, todo, log_path, on_trial=report)
            if not trials:
                raise RuntimeError('no trial ran on %s' % engine)
            for trial in trials:
                results[trial['spec']].append(trial)
            done = {t['spec'] for t in trials}
            todo = [s for s in todo if s not in done]
    return results


def summarize(spec_text, trials):
    """Mean, spread (sample standard deviation, max - min) of the measure of the spec's kind."""
    spec = parse_spec(spec_text)
    ok = [t for t in trials if not t['fell']]
    key = (lambda t: t['x_m']) if spec.kind == 'walk' else (lambda t: math.degrees(t['turned_rad']))
    values = [key(t) for t in ok]
    ys = [t['y_m'] for t in ok]

    def stats(v):
        if not v:
            return float('nan'), float('nan'), float('nan')
        return statistics.fmean(v), (statistics.stdev(v) if len(v) > 1 else 0.0), max(v) - min(v)

    mean, sd, span = stats(values)
    y_mean, y_sd, _ = stats(ys)
    sim = sum(t['sim_s'] for t in trials)
    wall = sum(t['wall_s'] for t in trials)
    return dict(spec=spec_text, kind=spec.kind, goal=spec.goal, fraction=spec.speed_fraction, n=len(trials),
                falls=len(trials) - len(ok), mean=mean, sd=sd, span=span, ratio=mean / spec.goal,
                y_mean=y_mean, y_sd=y_sd, real_time_factor=sim / wall if wall > 0 else float('nan'))
