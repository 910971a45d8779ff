"""Progress of a batch of runs (the competition, the robustness benchmark): on a terminal a live
tqdm bar with the elapsed time and a line per finished run; otherwise (a log file) a line when a
run starts and one when it ends."""
import sys
import threading


class Progress:
    def __init__(self, total: int, unit: str = "run"):
        self.total, self.started, self.bar = total, 0, None
        self._lock = threading.Lock()  # start() and done() are called from the worker threads
        if sys.stdout.isatty():
            from tqdm import tqdm
            self.bar = tqdm(total=total, unit=unit, dynamic_ncols=True,
                            bar_format="{desc} {n_fmt}/{total_fmt} [{elapsed}<{remaining}]")

    def start(self, name: str):
        with self._lock:
            self.started += 1
            if self.bar is not None:
                self.bar.set_description("running %s" % name)
            else:
                # one write per line: runs start and end from several threads
                print("[%d/%d] %s running ...\n" % (self.started, self.total, name), end="", flush=True)

    def done(self, line: str):
        with self._lock:
            if self.bar is not None:
                self.bar.write(line)
                self.bar.update(1)
            else:
                print(line + "\n", end="", flush=True)

    def close(self):
        if self.bar is not None:
            self.bar.close()
