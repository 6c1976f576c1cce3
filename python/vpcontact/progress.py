"""Progress of a run from Python: a tqdm bar where tqdm is installed (in a notebook
tqdm.auto's widget), else a one-line text bar rewritten in place (it works in a
terminal and in a notebook's output cell alike)."""

import sys
import time

__all__ = ["Bar", "bar"]


class Bar:
    """Called with each step's report (a dict of history.csv's numbers); the fraction done
    is t / T (fixed and varying step sizes alike). On a terminal or in a notebook the line
    is rewritten in place (at most 10 times a second); elsewhere (a log file) a line is
    printed about every 5 % of the time, as `vpcontact run` does."""

    def __init__(self, final_time, file=None, width=30):
        self.final_time = final_time
        self.file = file or sys.stderr
        self.width = width
        self.t0 = time.monotonic()
        self.drawn = 0.0
        self.logged = -1
        isatty = getattr(self.file, "isatty", lambda: False)
        self.in_place = isatty() or "ipykernel" in sys.modules

    def __call__(self, report):
        n, t = report["step"], report["t"]
        done = min(1.0, t / self.final_time) if self.final_time > 0 else 1.0
        last = done >= 1.0 - 1e-12
        now = time.monotonic()
        if self.in_place and not last and now - self.drawn < 0.1:
            return
        if not self.in_place and not last and int(20 * done) == self.logged:
            return
        self.drawn, self.logged = now, int(20 * done)
        filled = int(round(self.width * done))
        elapsed = now - self.t0
        eta = elapsed * (1 - done) / done if done > 0 else float("nan")
        line = "[%s%s] step %d  t = %.4g of %.4g  min beta = %.4g  %.1f s (ETA %.1f s)" % (
            "#" * filled, "." * (self.width - filled), n, t, self.final_time, report["beta_min"], elapsed, eta)
        self.file.write(("\r" + line + ("\n" if last else "")) if self.in_place else line + "\n")
        self.file.flush()

    def close(self):
        pass


class _Tqdm:
    """tqdm's bar in per cent of the final time."""

    def __init__(self, final_time, t):
        from tqdm.auto import tqdm

        self.final_time = final_time
        self.bar = tqdm(total=100, initial=self.percent(t), unit="%")

    def percent(self, t):
        return min(100, int(round(100 * t / self.final_time))) if self.final_time > 0 else 100

    def __call__(self, report):
        self.bar.update(self.percent(report["t"]) - self.bar.n)
        self.bar.set_postfix(step=report["step"], t="%.4g" % report["t"], beta_min="%.4g" % report["beta_min"])

    def close(self):
        self.bar.close()


def bar(final_time, t=0.0):
    """A progress callback for a run to `final_time`, now at t: tqdm's where installed, else Bar."""
    try:
        return _Tqdm(final_time, t)
    except ImportError:
        return Bar(final_time)
