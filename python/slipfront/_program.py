"""Finding and driving the `slipfront` program (docs/python.md, "How the package finds the program").

One function starts it, `drive`: the child runs in its own session, so a Ctrl-C at a terminal reaches
Python alone, which forwards one SIGINT to the child (the program then writes its partial results and
exits with 130: docs/cli.md "Stopping"); its stderr is read line by line, progress lines of
`--progress json` go to the caller's progress display, every other line is kept for messages.
"""
import json
import os
import queue
import shutil
import signal
import subprocess
import threading
from pathlib import Path

ENV = "SLIPFRONT_PROGRAM"


def find_program(program=None):
    """The slipfront executable: `program` if given, else $SLIPFRONT_PROGRAM, else the one installed
    beside this package (PREFIX/bin/slipfront for PREFIX/lib/python3/dist-packages/slipfront), else
    `slipfront` on PATH."""
    candidates = []
    if program:
        candidates.append(Path(program))
    elif os.environ.get(ENV):
        candidates.append(Path(os.environ[ENV]))
    else:
        here = Path(__file__).resolve().parent
        if len(here.parents) > 3:  # PREFIX/lib/python3/dist-packages/slipfront (or .../python3.X/site-packages/...)
            candidates.append(here.parents[3] / "bin" / "slipfront")
        found = shutil.which("slipfront")
        if found:
            candidates.append(Path(found))
    for c in candidates:
        if c.is_file() and os.access(c, os.X_OK):
            return str(c)
    raise FileNotFoundError(
        "the slipfront program was not found (looked at: %s); give program=..., or set %s to its path"
        % (", ".join(str(c) for c in candidates) or "nothing", ENV))


class Progress:
    """Progress of `--progress json` lines: a tqdm bar per model (tqdm.auto: a widget in a notebook) when
    tqdm is installed and `show` is True, a callable called with each line's dict, or nothing."""

    def __init__(self, show):
        self.callback = show if callable(show) else None
        self.tqdm = None
        if show is True:
            try:
                from tqdm.auto import tqdm
                self.tqdm = tqdm
            except ImportError:
                self.tqdm = None
        self.bar, self.key, self.ticks = None, None, []

    def update(self, tick):
        self.ticks.append(tick)
        if self.callback:
            self.callback(tick)
        if not self.tqdm:
            return
        if "study" in tick:
            key, total, n, unit = tick["study"], tick["runs"], tick["runs_done"], "run"
        else:
            key, total, n, unit = tick.get("model"), tick.get("t_end"), tick.get("t"), "t"
        if key != self.key:
            self.close()
            label = key if "study" in tick else "%s %s" % (tick.get("scene", ""), key)
            self.bar = self.tqdm(total=total, desc=label, unit=unit, leave=True)
            self.key = key
        if self.bar is not None and n is not None:
            self.bar.n = n
            self.bar.refresh()

    def close(self):
        if self.bar is not None:
            self.bar.close()
        self.bar, self.key = None, None


class Completed:
    """What a finished program left: exit code, stdout, stderr (progress lines taken out), progress ticks,
    and whether Python forwarded a Ctrl-C to it."""

    def __init__(self, args, code, stdout, stderr, ticks, interrupted):
        self.args, self.code, self.stdout, self.stderr = args, code, stdout, stderr
        self.ticks, self.interrupted = ticks, interrupted

    def errors(self):
        """The program's error lines, without their 'slipfront: error: ' prefix."""
        prefix = "slipfront: error: "
        return [l[len(prefix):] for l in self.stderr.splitlines() if l.startswith(prefix)]


def _read_lines(stream, sink, tag):
    for line in iter(stream.readline, ""):
        sink.put((tag, line))
    sink.put((tag, None))


def drive(args, progress=True, cwd=None, stop_after=None):
    """Runs `args` to its end and returns a Completed. On KeyboardInterrupt: one SIGINT to the child, then
    waits for it (a second KeyboardInterrupt sends a second SIGINT, which ends the program at once, as at a
    terminal). `stop_after(tick)` (tests) may return True to send SIGINT as if the user had pressed Ctrl-C."""
    display = Progress(progress)
    proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL,
                            text=True, errors="replace", cwd=cwd, start_new_session=True)
    lines = queue.Queue()
    readers = [threading.Thread(target=_read_lines, args=(proc.stdout, lines, "out"), daemon=True),
               threading.Thread(target=_read_lines, args=(proc.stderr, lines, "err"), daemon=True)]
    for r in readers:
        r.start()
    out, err, open_streams, interrupted = [], [], 2, False
    try:
        while open_streams:
            try:
                try:
                    tag, line = lines.get(timeout=0.1)
                except queue.Empty:
                    continue
                if line is None:
                    open_streams -= 1
                elif tag == "out":
                    out.append(line)
                elif line.startswith('{"slipfront":"progress"'):
                    tick = json.loads(line)
                    display.update(tick)
                    if stop_after and not interrupted and stop_after(tick):
                        interrupted = True
                        proc.send_signal(signal.SIGINT)
                else:
                    err.append(line)
            except KeyboardInterrupt:
                interrupted = True
                proc.send_signal(signal.SIGINT)
        code = _wait(proc)
    finally:
        display.close()
        if proc.poll() is None:  # an exception other than Ctrl-C: do not leave the program running
            proc.kill()
            proc.wait()
    return Completed(args, code, "".join(out), "".join(err), display.ticks, interrupted)


def _wait(proc):
    while True:
        try:
            return proc.wait()
        except KeyboardInterrupt:
            proc.send_signal(signal.SIGINT)
