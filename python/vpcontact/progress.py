"""Progress of a run from Python: a tqdm bar where tqdm is installed (in a notebook
tqdm.auto's widget), else a one-line text bar rewritten in place (it works in a
terminal and in a notebook's output cell alike)."""

import sys
import time

__all__ = ["Bar", "bar"]


class Bar:
    """Called with each step's report (a dict of history.csv's numbers). On a terminal or
    in a notebook the line is rewritten in place (at most 10 times a second); elsewhere
    (a log file) a line is printed about every 5 % of the steps, as `vpcontact run` does."""

    def __init__(self, total, file=None, width=30):
        self.total = total
        self.file = file or sys.stderr
        self.width = width
        self.t0 = time.monotonic()
        self.drawn = 0.0
        isatty = getattr(self.file, "isatty", lambda: False)
        self.in_place = isatty() or "ipykernel" in sys.modules
        self.every = max(1, total // 20)

    def __call__(self, report):
        n = report["step"]
        last = n >= self.total
        now = time.monotonic()
        if self.in_place and not last and now - self.drawn < 0.1:
            return
        if not self.in_place and not last and n % self.every:
            return
        self.drawn = now
        done = n / self.total if self.total else 1.0
        filled = int(round(self.width * done))
        elapsed = now - self.t0
        eta = elapsed * (1 - done) / done if done > 0 else float("nan")
        line = "[%s%s] step %d/%d  t = %.4g  min beta = %.4g  %.1f s (ETA %.1f s)" % (
            "#" * filled, "." * (self.width - filled), n, self.total, report["t"], report["beta_min"], elapsed, eta)
        self.file.write(("\r" + line + ("\n" if last else "")) if self.in_place else line + "\n")
        self.file.flush()

    def close(self):
        pass


class _Tqdm:
    def __init__(self, total, start):
        from tqdm.auto import tqdm

        self.bar = tqdm(total=total, initial=start, unit="step")

    def __call__(self, report):
        self.bar.update(report["step"] - self.bar.n)
        self.bar.set_postfix(t="%.4g" % report["t"], beta_min="%.4g" % report["beta_min"])

    def close(self):
        self.bar.close()


def bar(total, start=0):
    """A progress callback for `total` steps: tqdm's where installed, else Bar."""
    try:
        return _Tqdm(total, start)
    except ImportError:
        return Bar(total)
