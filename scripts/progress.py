"""Progress for the figure scripts: a line per item and a total, with an honest ETA.

    from progress import Progress
    bar = Progress(len(walks), "walks")
    for w in walks:
        bar.start(w)
        ...
        bar.done(w, "median 1.8 m")   # or bar.failed(w, "why")
    bar.finish()

On a terminal the current item's line is rewritten in place; otherwise (a log file, CI) one
line per finished item. Everything goes to stderr, so the scripts' tables on stdout stay
clean. Items may run in parallel threads (`start` and `done` take a lock). The ETA is the mean time of the finished items times those left: no guess before the
first item has finished. `FOOTSLAM_QUIET=1` silences it.
"""

import os
import sys
import threading
import time


def _clock(seconds):
    """`42 s`, `3m05s`, `1h02m`."""
    s = int(round(seconds))
    if s < 60:
        return f"{s} s"
    if s < 3600:
        return f"{s // 60}m{s % 60:02d}s"
    return f"{s // 3600}h{(s % 3600) // 60:02d}m"


class Progress:
    def __init__(self, total, what="items", stream=None):
        self.total = total
        self.what = what
        self.stream = stream or sys.stderr
        self.finished = 0
        self.failures = 0
        self.began = time.monotonic()
        self.quiet = os.environ.get("FOOTSLAM_QUIET") == "1"
        self.live = not self.quiet and hasattr(self.stream, "isatty") and self.stream.isatty()
        self.lock = threading.Lock()
        self.began_at = {}

    def wrap(self, work, name=str):
        """`work` with its item announced and finished: for `map` over a thread pool."""
        def run(item):
            self.start(name(item))
            try:
                result = work(item)
            except Exception as e:
                self.failed(name(item), e)
                raise
            self.done(name(item))
            return result
        return run

    def _eta(self):
        if self.finished == 0:
            return "eta —"
        per = (time.monotonic() - self.began) / self.finished
        return f"eta {_clock(per * (self.total - self.finished))}"

    def _write(self, text, final):
        if self.quiet:
            return
        if self.live:
            end = "\n" if final else ""
            self.stream.write("\r\033[K" + text + end)
        elif final:
            self.stream.write(text + "\n")
        self.stream.flush()

    def _prefix(self):
        return f"[{self.finished}/{self.total} {self.what}]"

    def start(self, name):
        """Item `name` begins."""
        with self.lock:
            now = time.monotonic()
            self.began_at[name] = now
            elapsed = _clock(now - self.began)
            self._write(f"{self._prefix()} {name} … ({elapsed}, {self._eta()})", final=False)

    def done(self, name, note=""):
        """Item `name` finished; `note` is what it gave."""
        with self.lock:
            self.finished += 1
            took = _clock(time.monotonic() - self.began_at.pop(name, self.began))
            tail = f": {note}" if note else ""
            self._write(f"{self._prefix()} {name} in {took}{tail} ({self._eta()})", final=True)

    def failed(self, name, why):
        """Item `name` failed with `why` (counted as finished)."""
        with self.lock:
            self.failures += 1
        self.done(name, f"FAILED {why}")

    def finish(self):
        """The total: items, failures, time."""
        failed = f", {self.failures} failed" if self.failures else ""
        took = _clock(time.monotonic() - self.began)
        self._write(f"{self.finished}/{self.total} {self.what} in {took}{failed}", final=True)
