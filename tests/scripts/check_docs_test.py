#!/usr/bin/env python3
"""scripts/check_docs.py finds what drifted in a doc's commands, and nothing else.

Usage: check_docs_test.py BUILD_DIR
"""

import os
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.path.abspath(sys.argv.pop(1)) if len(sys.argv) > 1 else os.path.join(ROOT, "build")

GOOD = """
```sh
build/lab/loom-lab --json precompute examples/fabrics/stockinette.json --out /tmp/x   # a comment
loom --server 127.0.0.1:7450 fabric precompute --no-wait --settings examples/precompute/standard.json \\
    examples/fabrics/stockinette.json
build/bench/loom_fit_benchmark --benchmark_filter='FitFabric/res:32/lobes:2/lut:1'
ctest --test-dir build -L stability -j2
cd web && npm run build && cd ..
bash scripts/setup.sh --with-browser
LOOM_TOKEN=$(cat tokens/client) build/client/loom server-info > /tmp/info.json 2>&1
```
"""

BAD = """
```sh
build/lab/loom-lab precompute --no-such-flag examples/fabrics/stockinette.json
build/lab/loom-lab render examples/scenes/no_such_scene.json --out out/x.png
loom fabric precompute --priorty 3 examples/fabrics/stockinette.json
build/bench/loom_fit_benchmark --benchmark_filter=NoSuchBenchmark
ctest --test-dir build -L no_such_label
cd web && npm run no-such-script
bash scripts/no_such_script.sh
```

See [the methods](../../docs/no_such_page.md) and [the README](../../README.md#run-it).

<!-- doc-check: skip -->
```sh
build/lab/loom-lab --skipped-flag
```
"""


def check(text, suffix=".md", *flags):
    # Beside this test, so that the page's relative links resolve in the repository.
    with tempfile.NamedTemporaryFile("w", suffix=suffix, dir=os.path.dirname(os.path.abspath(__file__)),
                                     delete=False) as doc:
        doc.write(text)
    try:
        run = subprocess.run([sys.executable, os.path.join(ROOT, "scripts/check_docs.py"), "--build", BUILD, *flags,
                              doc.name], capture_output=True, text=True)
    finally:
        os.unlink(doc.name)
    return run.returncode, run.stdout.splitlines()


class CheckDocsTest(unittest.TestCase):
    def test_current_commands_pass(self):
        code, problems = check(GOOD)
        self.assertEqual(problems, [])
        self.assertEqual(code, 0)

    def test_each_drift_is_reported_with_its_line(self):
        code, problems = check(BAD)
        self.assertEqual(code, 1)
        expected = [
            (3, "no option --no-such-flag"),
            (4, "examples/scenes/no_such_scene.json: no such file or folder"),
            (5, "no option --priorty"),
            (6, "no benchmark matches --benchmark_filter=NoSuchBenchmark"),
            (7, "ctest -L no_such_label: no such label"),
            (8, "npm run no-such-script: no such script in web/package.json"),
            (9, "scripts/no_such_script.sh: no such file or folder"),
            (12, "link ../../docs/no_such_page.md: no such file"),
        ]
        self.assertEqual(len(problems), len(expected), "\n".join(problems))
        problems.sort(key=lambda p: int(p.split(".md:")[1].split(":")[0]))
        for problem, (line, message) in zip(problems, expected):
            self.assertIn(f".md:{line}: ", problem)
            self.assertIn(message, problem)


    def test_measured_figures_in_comments_are_reported(self):
        source = """// Blending the shadings: better on the bench set (docs/accuracy.md).
int a;  // every 100 ms
// Bilinear: +1.6 dB on average over the nearest lookup.
/* a multi-line comment
 * where the cloth took 712 → 631 ms without it.
 */
"""
        code, problems = check(source, ".h", "--comments")
        self.assertEqual(code, 1)
        self.assertEqual(len(problems), 2, "\n".join(problems))
        self.assertIn(".h:3: a measured figure", problems[0])
        self.assertIn(".h:5: a measured figure", problems[1])


if __name__ == "__main__":
    unittest.main()
