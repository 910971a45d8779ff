"""The images of several cameras gathered into one set per frame (pure, no ROS).

The sign node judges the images of its cameras together and answers once per set (the lock-step
rule of its detections lists every camera's image topic; triggers that come in one frame owe one
answer). A set is the images of one capture time: it is complete when every camera that has ever
delivered an image has one of the newest stamp, so a camera that never publishes (not on this
robot, not yet subscribed) holds nothing up. The set's images come in the cameras' order, so the
tracker sees them in the same order run after run. An image older than the newest of its set
(a camera behind the others) is replaced by its camera's next one; an image of a capture time
already judged (a camera's first image, in the frame that was judged without it) is dropped; both
are counted. Only the first frame after a camera starts can differ between runs: which camera's
image of that frame is judged depends on the arrival order.
"""
from typing import Any, List, Optional, Sequence, Tuple


class ImageSets:
    def __init__(self, camera_count: int):
        if camera_count < 1:
            raise ValueError("camera_count must be >= 1, got %r" % (camera_count,))
        self.latest: List[Optional[Tuple[int, Any]]] = [None] * camera_count  # (stamp [ns], image)
        self.delivered = [False] * camera_count
        self.judged_up_to_ns: Optional[int] = None
        self.dropped = 0

    def restart(self):
        """Simulated time went back (a world reset): stamps start again."""
        self.latest = [None] * len(self.latest)
        self.judged_up_to_ns = None

    def add(self, camera: int, stamp_ns: int, image: Any) -> Optional[Sequence[Tuple[int, Any]]]:
        """Records a camera's image; returns the complete set [(camera, image)] in camera order, or
        None while a camera that has delivered before still owes its image of the newest stamp."""
        self.delivered[camera] = True
        if self.judged_up_to_ns is not None and stamp_ns <= self.judged_up_to_ns:
            self.dropped += 1
            return None
        if self.latest[camera] is not None:
            self.dropped += 1
        self.latest[camera] = (stamp_ns, image)
        newest_ns = max(entry[0] for entry in self.latest if entry is not None)
        if any(seen and (entry is None or entry[0] != newest_ns) for seen, entry in zip(self.delivered, self.latest)):
            return None
        out = [(i, entry[1]) for i, entry in enumerate(self.latest) if entry is not None]
        self.latest = [None] * len(self.latest)
        self.judged_up_to_ns = newest_ns
        return out
