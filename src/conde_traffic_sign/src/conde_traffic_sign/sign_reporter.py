"""When to report a recognised sign on the referee's V1 topic (pure, no ROS).

A sign is reported once it has been recognised, by name, in `confirm_frames` consecutive images
within `report_distance_m` of the camera.  It is not reported again until it has been out of
sight for `repeat_after_s` of simulated time (a new passing); repeat_after_s = 0 never repeats it,
which is what the referee wants: it judges each sign once per run, so a second lap's report of
the same sign would be judged against no unreported sign (sign_wrong).
"""
from typing import Dict, Iterable, List


class SignReporter:
    def __init__(self, confirm_frames: int = 3, report_distance_m: float = 1.8, repeat_after_s: float = 0.0):
        if confirm_frames < 1:
            raise ValueError("confirm_frames must be >= 1, got %r" % (confirm_frames,))
        if report_distance_m <= 0:
            raise ValueError("report_distance_m must be > 0, got %r" % (report_distance_m,))
        if repeat_after_s < 0:
            raise ValueError("repeat_after_s must be >= 0, got %r" % (repeat_after_s,))
        self.confirm_frames = confirm_frames
        self.report_distance_m = report_distance_m
        self.repeat_after_s = repeat_after_s
        self.streak: Dict[str, int] = {}
        self.reported_last_seen_s: Dict[str, float] = {}  # reported signs: when last recognised [s]

    def update(self, t_s: float, detections: Iterable) -> List[str]:
        """The names to report now, given one image's detections (objects with .name, .distance_m)."""
        near = {d.name for d in detections if d.distance_m <= self.report_distance_m}
        self.streak = {name: self.streak.get(name, 0) + 1 for name in near}
        out = []
        for name in sorted(near):
            last_s = self.reported_last_seen_s.get(name)
            if last_s is not None:
                if self.repeat_after_s == 0 or t_s - last_s < self.repeat_after_s:
                    self.reported_last_seen_s[name] = t_s
                    continue
            if self.streak[name] >= self.confirm_frames:
                self.reported_last_seen_s[name] = t_s
                out.append(name)
        return out
