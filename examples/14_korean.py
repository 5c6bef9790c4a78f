"""armkit in Korean (docs/languages.md): the same command with --lang ko, and the shell's messages in Korean.

Run: python examples/14_korean.py
"""

import io
import sys
from contextlib import redirect_stderr, redirect_stdout

import armkit
from armkit.cli import app


def armkit_command(*args):
    """Run ``armkit ARGS`` in this process and return what it printed and its exit code."""
    buf = io.StringIO()
    with redirect_stdout(buf), redirect_stderr(buf):
        try:
            app(list(args), standalone_mode=False)
            code = 0
        except SystemExit as exc:
            code = int(exc.code or 0)
    return buf.getvalue(), code


def main(out_dir=None):
    for lang in ("en", "ko"):
        text, code = armkit_command("fk", "fighter", "30", "45", "60", "--lang", lang)   # forgot --deg
        print(f"--lang {lang} (exit {code}):\n{text}")
    from rich.console import Console

    from armkit.cli.shell import Shell

    shell = Shell(armkit.load("fighter"), lang="ko", plot="none", console=Console(file=io.StringIO()))
    for line in ("ik 24.861 14.353 187.181", "ik 900 0 0"):
        print(f"shell> {line}\n{shell.execute(line).text}")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
