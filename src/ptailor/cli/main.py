"""``ptailor``: the command group. Library errors map to exit codes here and only here.

- bad arguments (click's usage errors) exit 2 with one line too;
- :class:`~ptailor.errors.PtailorError` and ``OSError`` (a file that cannot be read or
  written: permissions, a name too long, a full disk) exit 2 with one line on stderr,
  naming the file (never a hidden staging folder);
- a numeric failure of a solve (:class:`~ptailor.errors.NumericError`, a ``PtailorError``)
  exits 2 naming the step; ``MemoryError`` exits 2 with one line too;
- SIGINT and SIGTERM raise :class:`~ptailor.errors.Interrupted` (a ``KeyboardInterrupt``:
  staging folders are removed on the way out) and exit 128 + the signal (one that came as
  the output folder was put in place says the folder is complete); once the command has
  finished they are held until the process exits (its status is the command's);
- a closed stdout (``ptailor batch --json | head``) is no error: exit 141 (128 + SIGPIPE,
  as a shell shows a Unix tool the pipe ended) without a message;
- any other exception is an internal error, a bug: exit 1 with one line asking to report
  it (:func:`~ptailor.errors.internal_error`), Python's traceback only with ``--debug``;
- Python warnings and logging records from libraries (numpy, ezdxf) are captured for the
  run (``adjust`` puts them into the report's warnings) instead of being printed.
"""

from __future__ import annotations

import click

from ptailor import __version__
from ptailor.cli.adjust import adjust
from ptailor.cli.batch import batch
from ptailor.cli.demo import demo
from ptailor.cli.inspect import inspect
from ptailor.cli.measure import measure
from ptailor.cli.report import report
from ptailor.cli.validate import validate
from ptailor.cli.verify import verify


def one_line(text: str) -> str:
    """A message on one line, staging folder names replaced by their output folder's."""
    from ptailor.run.staging import hide_staging

    return hide_staging(" ".join(str(text).split()))


def os_error_message(exc: OSError) -> str:
    """``FILE: problem`` for an ``OSError``."""
    reason = exc.strerror or str(exc) or type(exc).__name__
    name = exc.filename if exc.filename is not None else exc.filename2
    return f"{name}: {reason}" if name is not None else reason


#: the BLAS thread variables ptailor sets to 1 unless the user set one
BLAS_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


def one_blas_thread() -> None:
    """One BLAS thread for the process, unless the user chose (read when numpy loads).

    The sparse factorisations and solves are single-threaded anyway; a second BLAS thread
    cost 15 % more CPU for the same wall time on a quiet 2-core machine (a 100k-triangle
    sleeve: 4.9-5.1 s against 4.2-4.3 s of CPU, byte-identical outputs) and oversubscribes
    the cores under load (batch workers, other jobs). Forked batch workers inherit it.
    """
    import os
    import sys

    if "numpy" in sys.modules or any(v in os.environ for v in BLAS_THREAD_VARIABLES):
        return
    for var in BLAS_THREAD_VARIABLES:
        os.environ[var] = "1"


def _on_signal(signum, frame) -> None:
    from ptailor.errors import Interrupted

    raise Interrupted(signum)


#: whether the command has finished (for :func:`_die`'s one line)
_FINISHED = False


def _die(signum, frame) -> None:
    """Before and after the command: a signal ends the process at once with 128 + it (the
    output is complete or not written; no "Aborted!" and no exit 1 from click), with its
    one line (a signal in the last milliseconds, after the output was in place, once ended
    the process without a word)."""
    import os
    import signal
    import sys

    for f in (sys.stdout, sys.stderr):
        with __import__("contextlib").suppress(Exception):
            f.flush()
    name = signal.Signals(signum).name
    what = (
        "after the command finished: its output is complete"
        if _FINISHED
        else "before the command started: nothing written"
    )
    with __import__("contextlib").suppress(OSError):
        os.write(2, f"ptailor: interrupted ({name}) {what}\n".encode())
    os._exit(128 + signum)


def _quiet_stdout() -> None:
    """Point stdout at /dev/null (a closed pipe: Python's exit would complain flushing it)."""
    import os
    import sys

    with __import__("contextlib").suppress(Exception):
        fd = os.open(os.devnull, os.O_WRONLY)
        os.dup2(fd, sys.stdout.fileno())


class _Group(click.Group):
    #: True when run as the program (``ptailor ...``: click reads sys.argv), not called with
    #: arguments (tests): then signals after the command end the process (:func:`_die`)
    _process = False

    def main(self, args=None, *rest, **kwargs):
        import contextlib
        import signal

        self._process = args is None
        if self._process:  # before the command starts nothing is written: end at once
            one_blas_thread()
            for s in (signal.SIGINT, signal.SIGTERM):
                with contextlib.suppress(ValueError, OSError):
                    signal.signal(s, _die)
        try:
            return super().main(args, *rest, **kwargs)
        finally:
            if self._process:  # Python's shutdown restores the default handlers: a late
                # signal then killed the finished process without a word (exit 130 with
                # OUT complete); held now, it changes nothing (the command's status)
                with contextlib.suppress(ValueError, OSError, AttributeError):
                    signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})

    def invoke(self, ctx: click.Context):
        import contextlib
        import signal

        from ptailor.errors import OUT_OF_MEMORY, Interrupted, PtailorError, internal_error
        from ptailor.run.library_warnings import capture_library_warnings

        saved = {}
        for s in (signal.SIGINT, signal.SIGTERM):
            with contextlib.suppress(ValueError, OSError):  # (only the main thread can)
                saved[s] = signal.signal(s, _on_signal)
        try:
            with capture_library_warnings():
                return super().invoke(ctx)
        except PtailorError as exc:
            click.echo(f"ptailor: error: {one_line(exc)}", err=True)
            ctx.exit(2)
        except click.UsageError as exc:  # one line too (not click's usage block)
            where = f" {exc.ctx.info_name}" if exc.ctx is not None and exc.ctx is not ctx else ""
            hint = f" (ptailor{where} --help)"
            click.echo(f"ptailor{where}: error: {one_line(exc.format_message())}{hint}", err=True)
            ctx.exit(2)
        except BrokenPipeError:  # stdout closed (| head): not bad input; end as Unix tools do
            _quiet_stdout()
            ctx.exit(128 + signal.SIGPIPE)
        except OSError as exc:
            click.echo(f"ptailor: error: {one_line(os_error_message(exc))}", err=True)
            ctx.exit(2)
        except KeyboardInterrupt as exc:
            signum = exc.signum if isinstance(exc, Interrupted) else signal.SIGINT
            name = signal.Signals(signum).name
            done = getattr(exc, "output_complete", None)  # (the signal came as OUT was put
            what = f"after {done} was written: it is complete" if done else "no partial output left"
            click.echo(f"ptailor: interrupted ({name}): {what}", err=True)
            ctx.exit(128 + signum)
        except (click.exceptions.Exit, click.exceptions.Abort, click.ClickException):
            raise  # click's own (Exit and Abort are RuntimeErrors)
        except MemoryError:  # neither the input's fault nor a bug
            click.echo(f"ptailor: error: {OUT_OF_MEMORY}; nothing written", err=True)
            ctx.exit(2)
        except Exception as exc:  # no known kind: a bug in ptailor
            if ctx.params.get("debug"):
                import traceback

                click.echo("".join(traceback.format_exception(exc)).rstrip(), err=True)
            more = "" if ctx.params.get("debug") else "; ptailor --debug shows the traceback"
            click.echo(f"ptailor: {one_line(internal_error(exc, more))}", err=True)
            ctx.exit(1)
        finally:
            global _FINISHED
            _FINISHED = True
            for s, h in saved.items():
                with contextlib.suppress(ValueError, OSError, TypeError):
                    signal.signal(s, _die if self._process else h)


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="ptailor")
@click.option(
    "--debug",
    is_flag=True,
    envvar="PTAILOR_DEBUG",
    help="On an internal error (a bug in ptailor), print Python's traceback too; batch: "
    "each garment's. Also PTAILOR_DEBUG=1.",
)
def cli(debug: bool) -> None:
    """Adjust sewing patterns after garments are edited in 3D.

    ptailor keeps what the designer built into a pattern (elastic cuffs, gathers, straight
    edges, matching seams) while the drape is scaled, shortened, extended or cut, following
    Qi & Igarashi's PerfectTailor (scale-preserving flattening).
    """


cli.add_command(adjust)
cli.add_command(inspect)
cli.add_command(measure)
cli.add_command(demo)
cli.add_command(batch)
cli.add_command(validate)
cli.add_command(verify)
cli.add_command(report)
