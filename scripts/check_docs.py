#!/usr/bin/env python3
"""Checks that the commands in the README's and docs' shell blocks still fit the code.

Every ```sh / ```bash block of README.md and docs/**/*.md is split into simple
commands (continuation lines joined, comments and redirections dropped, `cd` followed
within the block), and each is checked without running the slow ones:

- Loom's binaries (loom-lab, loom, loom-server, loom-worker, build/... paths): every
  subcommand exists and every option is in the --help of its subcommand or a parent;
- Google Benchmark programs: each --benchmark_filter matches at least one benchmark;
- `npm run NAME`: package.json of that directory has the script;
- `ctest -L LABEL` / `-R REGEX`: at least one test matches;
- scripts run by path or through bash/python3/node, and every argument that names a
  file or folder of the repository (bench/…, examples/…, docs/…): they exist;
- every relative Markdown link and image of the page: its file exists.

Arguments with a placeholder (an upper-case word such as DIR or SPEC, or "…") and paths
outside the repository are not checked. A line right before a block may say
`<!-- doc-check: skip -->` (not checked: it runs elsewhere) or
`<!-- doc-check: creates PATH … -->` (the block makes those paths; they need not exist).
With --comments, it also checks that no code comment outside tests/ holds a measured
figure (a number in dB, or a before → after in milliseconds): figures go stale with the
next sweep and belong in docs/, where they are reproducible.

Usage: check_docs.py [--build DIR] [--comments [SOURCE …]] [FILE.md …]; prints each
problem as FILE:LINE and exits 1 if there is any.
"""

import argparse
import fnmatch
import glob
import json
import os
import re
import shlex
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LOOM_BINARIES = {
    "loom-lab": "lab/loom-lab",
    "loom": "client/loom",
    "loom-server": "server/loom-server",
    "loom-worker": "worker/loom-worker",
}
RUNNERS = {"bash", "sh", "python3", "python", "node"}
OPERATORS = {"&&", "||", ";", "|", "&"}
REDIRECTIONS = {">", ">>", "<", "2>", "2>>", "&>", ">&", "2>&1", "1>&2"}
PLACEHOLDER = re.compile(r"(?<![a-z])[A-Z]{2,}(?![a-z])|…|<|\.\.\.|%|\$")


class Checker:
    def __init__(self, build):
        self.build = build
        self.problems = []
        self.helps = {}
        self.benchmarks = {}
        self.ctest = None
        self.created = []
        self.commands = 0

    def problem(self, where, message):
        self.problems.append(f"{where}: {message}")

    # --- blocks and commands -------------------------------------------------
    def check_file(self, path):
        rel = os.path.relpath(path, ROOT)
        lines = open(path, encoding="utf-8").read().split("\n")
        self.check_links(rel, path, lines)
        i = 0
        while i < len(lines):
            fence = re.match(r"^\s*```\s*(\w*)", lines[i])
            if not fence:
                i += 1
                continue
            note = lines[i - 1] if i > 0 else ""
            skip = "doc-check: skip" in note
            created = re.search(r"doc-check: creates (.*?)\s*-->", note)
            start = i + 1
            i = start
            while i < len(lines) and not re.match(r"^\s*```", lines[i]):
                i += 1
            if fence.group(1) in ("sh", "bash") and not skip:
                self.created = created.group(1).split() if created else []
                self.check_block(rel, start, lines[start:i])
            i += 1

    def check_links(self, rel, path, lines):
        fenced = False
        for number, line in enumerate(lines, 1):
            if re.match(r"^\s*```", line):
                fenced = not fenced
            if fenced:
                continue
            for target in re.findall(r"\]\(([^)\s]+)\)", line):
                if re.match(r"^([a-z]+:|#)", target):
                    continue
                file = os.path.normpath(os.path.join(os.path.dirname(path), target.split("#", 1)[0]))
                if not os.path.exists(file):
                    self.problem(f"{rel}:{number}", f"link {target}: no such file")

    def check_block(self, rel, first_line, lines):
        cwd = ROOT
        for number, text in joined_lines(lines, first_line):
            where = f"{rel}:{number}"
            if text.startswith("$ "):
                text = text[2:]
            text = re.sub(r"\$\([^()]*\)", "SUBSTITUTION", text)
            try:
                lexer = shlex.shlex(text, posix=True, punctuation_chars=";&|<>")
                lexer.whitespace_split = True
                lexer.commenters = "#"
                tokens = list(lexer)
            except ValueError as error:
                self.problem(where, f"does not parse as a shell line ({error}): {text}")
                continue
            for command in split_commands(tokens):
                cwd = self.check_command(where, command, cwd)

    def check_command(self, where, command, cwd):
        while command and re.match(r"^[A-Za-z_][A-Za-z0-9_]*=", command[0]):
            command = command[1:]
        if command and command[0] == "sudo":
            command = command[1:]
        if not command:
            return cwd
        program, args = command[0], command[1:]
        self.commands += 1
        if program == "cd":
            target = os.path.normpath(os.path.join(cwd, args[0])) if args else ROOT
            if not inside(target):
                return target
            if not os.path.isdir(target):
                self.problem(where, f"cd {args[0]}: no such folder")
                return cwd
            return target
        name = os.path.basename(program)
        if name in LOOM_BINARIES and (program == name or program.endswith(LOOM_BINARIES[name])):
            self.check_loom(where, os.path.join(self.build, LOOM_BINARIES[name]), program, args)
        elif name.endswith("_benchmark"):
            self.check_benchmark(where, os.path.join(self.build, "bench", name), args)
        elif program in ("npm", "npx") and args[:1] == ["run"] and len(args) > 1:
            self.check_npm_script(where, cwd, args[1])
        elif program == "ctest":
            self.check_ctest(where, args)
        elif program in RUNNERS and args and not args[0].startswith("-"):
            self.check_path(where, cwd, args[0], must=True)
            args = args[1:]
        elif "/" in program:
            self.check_path(where, cwd, program, must=True)
        for arg in args:
            value = arg.split("=", 1)[1] if arg.startswith("--") and "=" in arg else arg
            self.check_path(where, cwd, value, must=False)
        return cwd

    # --- paths ----------------------------------------------------------------
    def check_path(self, where, cwd, value, must):
        value = value.strip("()")
        if PLACEHOLDER.search(value) or value.startswith("-") or "://" in value:
            return
        full = os.path.normpath(os.path.join(cwd, value))
        if not inside(full):
            return
        rel = os.path.relpath(full, ROOT)
        if any(rel == c or rel.startswith(c.rstrip("/") + "/") for c in self.created):
            return
        top = rel.split(os.sep)[0]
        if top == "build":
            full = os.path.join(self.build, os.path.relpath(full, os.path.join(ROOT, "build")))
        elif not must and ("/" not in value or top.startswith(".") or not os.path.isdir(os.path.join(ROOT, top))):
            # Only arguments that name something in a folder of the repository are paths.
            return
        if not must and top in ("build", "out"):
            return
        if not glob.glob(full):
            self.problem(where, f"{value}: no such file or folder")

    # --- Loom's binaries -------------------------------------------------------
    def help_of(self, binary, chain):
        key = (binary, tuple(chain))
        if key not in self.helps:
            run = subprocess.run([binary, *chain, "--help"], capture_output=True, text=True)
            self.helps[key] = run.stdout + run.stderr if run.returncode == 0 else None
        return self.helps[key]

    def check_loom(self, where, binary, program, args):
        if not os.access(binary, os.X_OK):
            self.problem(where, f"{program}: {binary} is not built")
            return
        chain, helps = [], [self.help_of(binary, [])]
        for arg in args:
            if arg.startswith("-"):
                continue
            section = helps[-1].split("Subcommands:", 1)
            names = re.findall(r"^\s{2}(\S+)", section[1], re.M) if len(section) == 2 else []
            if arg in names:
                chain.append(arg)
                helps.append(self.help_of(binary, chain))
                if helps[-1] is None:
                    self.problem(where, f"{program} {' '.join(chain)} --help fails")
                    return
        for arg in args:
            if not arg.startswith("-") or arg == "-":
                continue
            flag = arg.split("=", 1)[0]
            pattern = re.compile(r"(^|[\s,])" + re.escape(flag) + r"(?=[\s,=]|$)", re.M)
            if not any(pattern.search(h) for h in helps):
                self.problem(where, f"{program} {' '.join(chain)}: no option {flag}")

    def check_benchmark(self, where, binary, args):
        if not os.access(binary, os.X_OK):
            self.problem(where, f"{binary} is not built")
            return
        # Flags of the program's own (fit_benchmark's --samples) may register benchmarks.
        own = tuple(arg for arg in args if not arg.startswith("--benchmark_"))
        if (binary, own) not in self.benchmarks:
            run = subprocess.run([binary, *own, "--benchmark_list_tests=true"], capture_output=True, text=True)
            self.benchmarks[(binary, own)] = run.stdout.split()
        for arg in args:
            if arg.startswith("--benchmark_filter="):
                pattern = re.compile(arg.split("=", 1)[1])
                if not any(pattern.search(name) for name in self.benchmarks[(binary, own)]):
                    self.problem(where, f"{os.path.basename(binary)}: no benchmark matches {arg}")

    # --- npm and ctest ---------------------------------------------------------
    def check_npm_script(self, where, cwd, script):
        package = os.path.join(cwd, "package.json")
        scripts = json.load(open(package)).get("scripts", {}) if os.path.exists(package) else {}
        if script not in scripts:
            self.problem(where, f"npm run {script}: no such script in {os.path.relpath(package, ROOT)}")

    def check_ctest(self, where, args):
        if self.ctest is None:
            run = subprocess.run(["ctest", "--test-dir", self.build, "-N", "--print-labels"],
                                 capture_output=True, text=True)
            labels = re.findall(r"^\s+(\S+)$", run.stdout.split("All Labels:", 1)[-1], re.M)
            run = subprocess.run(["ctest", "--test-dir", self.build, "-N"], capture_output=True, text=True)
            self.ctest = (labels, re.findall(r"Test\s+#\d+: (\S+)", run.stdout))
        labels, names = self.ctest
        for flag, value in zip(args, args[1:]):
            if flag == "-L" and not any(re.search(value, label) for label in labels):
                self.problem(where, f"ctest -L {value}: no such label")
            if flag == "-R" and not any(re.search(value, name) for name in names):
                self.problem(where, f"ctest -R {value}: no test matches")


SOURCE_DIRS = ("core", "server", "worker", "client", "lab", "rpc", "bench", "fuzz")
SOURCE_SUFFIXES = (".h", ".cpp", ".glsl", ".frag", ".vert", ".comp")
MEASURED = re.compile(r"(//|^\s*\*).*(\d ?dB\b|\d ?(ms )?→ ?\d+(\.\d+)? ?ms\b)")


def comment_figures(checker, paths):
    """Code comments with a measured figure (MEASURED)."""
    for path in paths:
        for number, line in enumerate(open(path, encoding="utf-8", errors="replace"), 1):
            if MEASURED.search(line):
                checker.problem(f"{os.path.relpath(path, ROOT)}:{number}",
                                "a measured figure in a comment (put it in docs/): " + line.strip())


def sources():
    for top in SOURCE_DIRS:
        for folder, _, names in os.walk(os.path.join(ROOT, top)):
            yield from (os.path.join(folder, n) for n in sorted(names) if n.endswith(SOURCE_SUFFIXES))


def inside(path):
    return os.path.commonpath([os.path.abspath(path), ROOT]) == ROOT


def joined_lines(lines, first_line):
    """(line number, text) per logical line: continuations joined, blank and comment lines dropped."""
    pending, start = "", None
    for offset, line in enumerate(lines):
        if start is None:
            start = first_line + offset + 1
        stripped = line.rstrip()
        if stripped.endswith("\\"):
            pending += stripped[:-1] + " "
            continue
        text = (pending + stripped).strip()
        pending = ""
        if text and not text.startswith("#"):
            yield start, text
        start = None


def split_commands(tokens):
    command, skip_next = [], False
    for token in tokens:
        if skip_next:
            skip_next = False
            continue
        if token in OPERATORS:
            if command:
                yield command
            command = []
        elif token in REDIRECTIONS or re.fullmatch(r"\d?[<>]+&?\d?", token):
            skip_next = not re.fullmatch(r"\d?>&\d", token)
        else:
            command.append(token)
    if command:
        yield command


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--comments", action="store_true", help="check code comments instead of docs")
    parser.add_argument("files", nargs="*")
    options = parser.parse_args()
    checker = Checker(os.path.abspath(options.build))
    if options.comments:
        files = options.files or list(sources())
        comment_figures(checker, files)
    else:
        files = options.files or [os.path.join(ROOT, "README.md")] + sorted(
            f for f in glob.glob(os.path.join(ROOT, "docs", "**", "*.md"), recursive=True))
        for path in files:
            checker.check_file(os.path.abspath(path))
    for problem in checker.problems:
        print(problem)
    checked = f"{len(files)} files" + ("" if options.comments else f", {checker.commands} commands")
    print(f"{checked}, {len(checker.problems)} problems", file=sys.stderr)
    return 1 if checker.problems else 0


if __name__ == "__main__":
    sys.exit(main())
