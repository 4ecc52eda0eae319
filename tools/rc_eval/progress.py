"""A progress bar on stderr when it is a terminal; silent otherwise (logs, tests)."""
import sys
import time


class Progress:
    def __init__(self, total, label, stream=sys.stderr):
        self.total, self.label, self.stream = max(total, 1), label, stream
        self.done, self.start = 0, time.monotonic()
        self.tty = hasattr(stream, "isatty") and stream.isatty()

    def step(self, what=""):
        self.done += 1
        if not self.tty:
            return
        frac = self.done / self.total
        bar = "#" * int(30 * frac) + "-" * (30 - int(30 * frac))
        self.stream.write("\r%s [%s] %d/%d %4.0fs %-30s" % (self.label, bar, self.done, self.total,
                                                        time.monotonic() - self.start, what[:30]))
        if self.done >= self.total:
            self.stream.write("\n")
        self.stream.flush()
