#!/usr/bin/python3
"""Black-box fuzz of the d2vdb command's options (its files are fuzzed by tools/fuzz.sh).

Every sub-command is run with mutated options on small valid inputs, and each run is judged:

  crash     the process died of a signal (abort, segmentation fault, ...);
  hang      it ran past --timeout seconds (an absurd option must be refused up front, not run);
  exit 3    it failed with the "internal error / out of memory" code on what is bad input
            (exit 2 is the answer to bad input);
  memory    its peak resident memory passed --max-rss-mb;
  lost      it failed (exit code not 0) but replaced or removed a file that existed before it
            ran: every output argument is created beforehand with a sentinel text, which a failed
            run must leave as it was.

The command lines come from tools/compare-outputs.py (every sub-command, most of them several
times, on the bundled volumes and on inputs it generates): they are first run once unchanged in
WORKDIR/base, so that the inputs and the outputs that later commands read exist, then mutated at
random (seeded, so a run can be repeated):

  * a numeric value becomes an extreme one (0, -1, 1e-300, 1e300, nan, inf, 2^31, ...), or is
    scaled by a plausible factor (0.01 to 1000, integers kept integers) that the option parser
    accepts, so that the run reaches the engine's budgets and checks; a list value (x,y,z) loses
    or gains a component or gets one extreme component;
  * an option of the sub-command's --help is added with such a value, or with a file of another
    kind;
  * an argument is dropped or an option repeated;
  * an input is swapped for an input of another kind, a truncated copy or a missing path;
  * an output goes into a missing folder or gets another extension.

Use:
  tools/fuzz-options.py BINARY WORKDIR [--minutes 10] [--seed 1] [--timeout 60]
                        [--max-rss-mb 4096]

Findings go to WORKDIR/findings.json (command line, kind, exit code, seconds, peak memory and
the first lines of stderr) and are summarized on stdout; the exit status is 1 when there is any
finding, 0 otherwise. WORKDIR must not exist or be an earlier run's folder.
"""

import argparse
import importlib.util
import json
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import time

SCRIPT_DIR = os.path.dirname(os.path.abspath(__file__))
SENTINEL = b"d2vdb options fuzz: this file existed before the run\n"
EXTREME_NUMBERS = ("0", "-0", "-1", "1", "1e-300", "1e-30", "1e-7", "1e9", "1e30", "1e300", "nan",
                   "inf", "-inf", "2147483648", "-2147483649", "99999999999999999999", "65536",
                   "4096", "100000", "0.5", "-1e-9", "3.7", "")
LIST_VALUE = re.compile(r"^-?[0-9.eE+-]+(,-?[0-9.eE+-]+)+$")
NUMBER_VALUE = re.compile(r"^-?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")
HELP_OPTION = re.compile(r"^\s+(?:-\w,\s*)?(--[a-z][a-z0-9-]*)", re.M)
OUTPUT_EXTENSIONS = (".vdb", ".obj", ".ply", ".stl", ".json", ".svg", ".xyz", ".csv")


def load_compare_outputs():
    spec = importlib.util.spec_from_file_location(
        "compare_outputs", os.path.join(SCRIPT_DIR, "compare-outputs.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


class MeasuredPopen(subprocess.Popen):
    """A Popen that reaps its child with wait4 and keeps that child's own peak resident memory
    (RUSAGE_CHILDREN would give the largest of all children so far)."""

    def _try_wait(self, wait_flags):
        try:
            pid, status, usage = os.wait4(self.pid, wait_flags)
        except ChildProcessError:
            pid, status = self.pid, 0
            usage = None
        if pid == self.pid and usage is not None:
            self.peak_rss_mb = usage.ru_maxrss / 1024.0  # Linux: kilobytes
        return (pid, status)


def run_once(binary, arguments, folder, timeout):
    """Runs d2vdb ARGUMENTS in FOLDER; returns (exit code or 'signal N' or 'timeout', seconds,
    peak resident memory in MB, stderr bytes)."""
    clock = time.monotonic()
    process = MeasuredPopen(["d2vdb"] + arguments, executable=binary, cwd=folder,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            env=dict(os.environ, LC_ALL="C"), start_new_session=True)
    try:
        _, err = process.communicate(timeout=timeout)
        timed_out = False
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        _, err = process.communicate()
        timed_out = True
    seconds = time.monotonic() - clock
    peak = getattr(process, "peak_rss_mb", None)
    if timed_out:
        return "timeout", seconds, peak, err
    if process.returncode < 0:
        return "signal %d" % -process.returncode, seconds, peak, err
    return process.returncode, seconds, peak, err


def help_options(binary, subcommand):
    result = subprocess.run(["d2vdb", subcommand, "--help"], executable=binary,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=30)
    options = sorted(set(HELP_OPTION.findall(result.stdout.decode("utf-8", "replace"))))
    return [option for option in options if option not in ("--help", "--threads")]


def looks_like_output(argument, folder):
    """A bare file name in the command's own folder that does not exist yet: an output."""
    return ("/" not in argument and not argument.startswith("-") and
            os.path.splitext(argument)[1].lower() in OUTPUT_EXTENSIONS and
            not os.path.exists(os.path.join(folder, argument)))


SCALE_FACTORS = (0.01, 0.1, 0.5, 2.0, 3.0, 10.0, 100.0, 1000.0)


def scaled(value, rng):
    """VALUE (a number or an x,y,z list) times a plausible factor: values the option parser
    accepts, so that the run reaches the engine (its budgets and checks) instead of stopping at
    the parser's range checks as most extreme values do. Integers stay integers."""
    factor = rng.choice(SCALE_FACTORS)

    def one(part):
        if re.match(r"^-?\d+$", part):
            return str(max(1, int(round(int(part) * factor))) if int(part) > 0 else int(part))
        return "%.6g" % (float(part) * factor)

    try:
        return ",".join(one(part) for part in value.split(","))
    except ValueError:
        return value


class Mutator:
    def __init__(self, rng, inputs, options_of):
        self.rng = rng
        self.inputs = inputs
        self.options_of = options_of

    def extreme_value(self):
        rng = self.rng
        roll = rng.random()
        if roll < 0.6:
            return rng.choice(EXTREME_NUMBERS)
        if roll < 0.8:
            count = rng.choice((1, 2, 3, 4))
            return ",".join(rng.choice(EXTREME_NUMBERS[:14]) for _ in range(count))
        return rng.choice(self.inputs)

    def mutate(self, arguments):
        rng = self.rng
        arguments = list(arguments)
        subcommand = next((a for a in arguments if not a.startswith("-") and
                           not NUMBER_VALUE.match(a)), None)
        for _ in range(rng.choice((1, 1, 2, 3))):
            kind = rng.random()
            numeric = [i for i, a in enumerate(arguments) if NUMBER_VALUE.match(a) or
                       LIST_VALUE.match(a)]
            paths = [i for i, a in enumerate(arguments) if a.startswith("../")]
            outputs = [i for i, a in enumerate(arguments) if os.path.splitext(a)[1].lower() in
                       OUTPUT_EXTENSIONS and not a.startswith("../")]
            if kind < 0.35 and numeric:
                i = rng.choice(numeric)
                if LIST_VALUE.match(arguments[i]) and rng.random() < 0.5:
                    parts = arguments[i].split(",")
                    action = rng.choice(("drop", "add", "replace"))
                    if action == "drop":
                        parts.pop()
                    elif action == "add":
                        parts.append(rng.choice(EXTREME_NUMBERS[:14]))
                    else:
                        parts[rng.randrange(len(parts))] = rng.choice(EXTREME_NUMBERS[:14])
                    arguments[i] = ",".join(parts)
                elif rng.random() < 0.5:
                    arguments[i] = scaled(arguments[i], rng)
                else:
                    arguments[i] = rng.choice(EXTREME_NUMBERS)
            elif (kind < 0.65 and subcommand in arguments and  # an earlier drop can take it
                  self.options_of.get(subcommand)):
                option = rng.choice(self.options_of[subcommand])
                position = rng.randrange(arguments.index(subcommand) + 1, len(arguments) + 1)
                arguments[position:position] = [option, self.extreme_value()]
            elif kind < 0.75 and len(arguments) > 3:
                del arguments[rng.randrange(3, len(arguments))]
            elif kind < 0.8:
                options = [i for i, a in enumerate(arguments) if a.startswith("--")]
                if options:
                    i = rng.choice(options)
                    take = 2 if i + 1 < len(arguments) and not arguments[i + 1].startswith("-") \
                        else 1
                    arguments.extend(arguments[i:i + take])
            elif kind < 0.92 and paths:
                i = rng.choice(paths)
                arguments[i] = rng.choice(self.inputs + ["../inputs/missing.obj",
                                                         "../inputs/truncated.vdb"])
            elif outputs:
                i = rng.choice(outputs)
                stem, _ = os.path.splitext(arguments[i])
                arguments[i] = rng.choice(("no-such-folder/" + arguments[i],
                                           stem + rng.choice(OUTPUT_EXTENSIONS), stem))
        return arguments


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("binary")
    parser.add_argument("workdir")
    parser.add_argument("--minutes", type=float, default=10.0)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--timeout", type=float, default=60.0)
    parser.add_argument("--max-rss-mb", type=float, default=4096.0)
    args = parser.parse_args()
    binary = os.path.abspath(args.binary)
    compare = load_compare_outputs()
    if os.path.exists(args.workdir):
        if not os.path.exists(os.path.join(args.workdir, "base", "manifest.json")):
            raise SystemExit("fuzz-options: %s exists and is not an earlier run" % args.workdir)
        shutil.rmtree(args.workdir)
    os.makedirs(args.workdir)
    base = os.path.join(args.workdir, "base")
    print("== running the unmutated command list once in %s" % base)
    sys.stdout.flush()
    compare.run_all(binary, base, compare.DEFAULT_VOLUMES)
    commands = compare.order_dependencies(compare.command_list())
    inputs = sorted("../inputs/" + name for name in os.listdir(os.path.join(base, "inputs")))
    options_of = {sub: help_options(binary, sub) for sub in compare.SUBCOMMANDS}
    rng = random.Random(args.seed)
    mutator = Mutator(rng, inputs, options_of)
    findings, exits, runs = [], {}, 0
    deadline = time.monotonic() + 60.0 * args.minutes
    print("== fuzzing for %.1f minutes (seed %d)" % (args.minutes, args.seed))
    sys.stdout.flush()
    while time.monotonic() < deadline:
        _, arguments = rng.choice(commands)
        mutated = mutator.mutate(arguments)
        folder = os.path.join(base, "fuzz-%06d" % runs)
        os.makedirs(folder)
        sentinels = [a for a in mutated if looks_like_output(a, folder)]
        for name in sentinels:
            with open(os.path.join(folder, name), "wb") as file:
                file.write(SENTINEL)
        exit_code, seconds, peak, err = run_once(binary, mutated, folder, args.timeout)
        runs += 1
        exits[str(exit_code)] = exits.get(str(exit_code), 0) + 1
        kinds = []
        if isinstance(exit_code, str):
            kinds.append("hang" if exit_code == "timeout" else "crash")
        elif exit_code == 3:
            kinds.append("exit 3")
        if peak is not None and peak > args.max_rss_mb:
            kinds.append("memory")
        if exit_code != 0:
            for name in sentinels:
                path = os.path.join(folder, name)
                if not os.path.exists(path) or open(path, "rb").read() != SENTINEL:
                    kinds.append("lost")
                    break
        if kinds:
            finding = {"kinds": kinds, "command": "d2vdb " + " ".join(mutated),
                       "folder": os.path.relpath(folder, args.workdir), "exit": exit_code,
                       "seconds": round(seconds, 2),
                       "peak_rss_mb": None if peak is None else round(peak, 1),
                       "stderr": err.decode("utf-8", "replace").splitlines()[-5:]}
            findings.append(finding)
            print("FINDING %s: %s (exit %s, %.1f s, %s MB)" % (
                "+".join(kinds), finding["command"], exit_code, seconds, finding["peak_rss_mb"]))
            sys.stdout.flush()
        else:
            shutil.rmtree(folder)
    summary = {"binary": binary, "seed": args.seed, "minutes": args.minutes, "runs": runs,
               "exit_codes": exits, "timeout_seconds": args.timeout,
               "max_rss_mb": args.max_rss_mb, "findings": findings}
    with open(os.path.join(args.workdir, "findings.json"), "w") as file:
        json.dump(summary, file, indent=1)
        file.write("\n")
    print("== %d mutated runs, exit codes %s, %d findings (%s)" % (
        runs, json.dumps(exits, sort_keys=True), len(findings),
        os.path.join(args.workdir, "findings.json")))
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
