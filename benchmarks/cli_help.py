"""Seconds `soccer-lab --help` and every subcommand's `--help` take, as a user runs them (a fresh process each
time, the installed console script). Target: under 0.5 s each.

    python benchmarks/cli_help.py [--runs 7] [--importtime COMMAND] [--record]

Every command is found by walking the CLI itself, so a new command is timed without editing this script.
Each figure is the median of --runs fresh processes. `--importtime "rules usage"` also prints the 15 modules
that command's help spends most time importing (`python -X importtime`), to see what to import lazily.
"""

from __future__ import annotations

import argparse
import resource
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

import typer.main

from results import Figure, add_record_option, load_average, record, this_command

TARGET_SECONDS = 0.5


def console_script() -> list[str]:
    """The `soccer-lab` executable installed beside this Python (else: this Python running soccer_lab.app.cli)."""
    script = Path(sys.executable).parent / "soccer-lab"
    if script.exists():
        return [str(script)]
    return [sys.executable, "-c", "from soccer_lab.app.cli import main; main()"]


def command_paths() -> list[list[str]]:
    """Every command path of the CLI, the root first: [], ["evolve"], ["rules"], ["rules", "check"], ..."""
    from soccer_lab.app.cli import app

    root = typer.main.get_command(app)
    paths: list[list[str]] = []

    def walk(command, path: list[str]) -> None:
        paths.append(path)
        context = command.context_class(command, info_name=" ".join(["soccer-lab", *path]))
        for name in getattr(command, "list_commands", lambda _: [])(context):
            walk(command.get_command(context, name), [*path, name])

    walk(root, [])
    return paths


def seconds(arguments: list[str], runs: int) -> tuple[float, float]:
    """Median wall time and median CPU time (user + system) of `runs` fresh processes. On a busy machine
    the wall time waits for a core; the CPU time is close to what the wall time is on a quiet one."""
    walls, cpus = [], []
    for _ in range(runs):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        started = time.perf_counter()
        subprocess.run(arguments, check=True, stdout=subprocess.DEVNULL)
        walls.append(time.perf_counter() - started)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpus.append(after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime)
    return statistics.median(walls), statistics.median(cpus)


def slowest_imports(path: list[str], count: int = 15) -> list[str]:
    code = f"import sys; sys.argv = {['soccer-lab', *path, '--help']!r}; from soccer_lab.app.cli import main; main()"
    done = subprocess.run([sys.executable, "-X", "importtime", "-c", code], capture_output=True, text=True)
    rows = []
    for line in done.stderr.splitlines():
        parts = line.removeprefix("import time:").split("|")
        if len(parts) == 3 and parts[1].strip().isdigit():
            rows.append((int(parts[1]), parts[2].rstrip()))
    return [f"{micro / 1e6:6.3f} s {name}" for micro, name in sorted(rows, reverse=True)[:count]]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--runs", type=int, default=7, help="fresh processes per command (the median is shown)")
    parser.add_argument("--importtime", metavar="COMMAND", help='e.g. "" for the root, "evolve", "rules usage"')
    add_record_option(parser)
    args = parser.parse_args()
    if shutil.which("soccer-lab") is None and not Path(sys.executable).with_name("soccer-lab").exists():
        print("note: soccer-lab is not installed beside this Python; timing `python -c` instead", file=sys.stderr)
    load_before = load_average()
    base = console_script()
    timed = [(path, *seconds([*base, *path, "--help"], args.runs)) for path in command_paths()]
    width = max(len(" ".join(path)) for path, _, _ in timed) + len("soccer-lab  --help")
    print(f"{'command':<{width}} {'wall':>7} {'cpu':>7}")
    for path, wall, cpu in timed:
        print(f"{' '.join(['soccer-lab', *path, '--help']):<{width}} {wall:6.3f}s {cpu:6.3f}s")
    slowest_path, slowest, slowest_cpu = max(timed, key=lambda item: item[1])
    verdict = "met" if slowest < TARGET_SECONDS else "MISSED"
    print(f"slowest: {' '.join(['soccer-lab', *slowest_path])} --help {slowest:.3f} s wall, {slowest_cpu:.3f} s CPU "
          f"(target < {TARGET_SECONDS} s: {verdict}); load average {load_before} before, {load_average()} after")
    if args.importtime is not None:
        print(f"\nslowest imports of `soccer-lab {args.importtime} --help` (cumulative):")
        print("\n".join(slowest_imports(args.importtime.split())))
    if args.record:
        root = next(wall for path, wall, _ in timed if not path)
        record("cli_help", [
            Figure("soccer-lab --help", round(root, 3), "s", target=f"< {TARGET_SECONDS} s"),
            Figure("slowest subcommand --help", round(slowest, 3), "s", target=f"< {TARGET_SECONDS} s",
                   note=f"soccer-lab {' '.join(slowest_path)} --help; {slowest_cpu:.3f} s of CPU"),
        ], command=this_command(), load_before=load_before)


if __name__ == "__main__":
    main()
