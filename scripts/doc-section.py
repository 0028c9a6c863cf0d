#!/usr/bin/env python3
"""Keeps a generated section of a Markdown file equal to a program's output.

The section lies between the lines `<!-- generated: NAME -->` and `<!-- end generated: NAME -->`;
everything else in the file is written by hand.

  scripts/doc-section.py --check docs/ros.md node-params -- build/apps/pensight_node --params
  scripts/doc-section.py --write docs/ros.md node-params -- build/apps/pensight_node --params

--check exits 1 (naming the --write command) when the section differs; --write replaces it.
"""
import argparse
import subprocess
import sys
from pathlib import Path


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    mode = parser.add_mutually_exclusive_group(required=True)
    mode.add_argument("--check", action="store_true", help="exit 1 when the section is stale")
    mode.add_argument("--write", action="store_true", help="replace the section")
    parser.add_argument("file", type=Path)
    parser.add_argument("name", help="the section's name in its marker lines")
    parser.add_argument("command", nargs=argparse.REMAINDER, help="-- PROGRAM ARGS...")
    args = parser.parse_args()
    command = args.command[1:] if args.command[:1] == ["--"] else args.command
    if not command:
        parser.error("give the program after --")

    begin, end = f"<!-- generated: {args.name} -->\n", f"<!-- end generated: {args.name} -->\n"
    try:
        text = args.file.read_text()
    except OSError as e:
        print(f"doc-section: cannot read {args.file}: {e.strerror}", file=sys.stderr)
        return 2
    if text.count(begin) != 1 or text.count(end) != 1 or text.index(begin) > text.index(end):
        print(f"doc-section: {args.file} needs one '{begin.strip()}' line followed by one "
              f"'{end.strip()}' line", file=sys.stderr)
        return 2
    generated = subprocess.run(command, check=True, capture_output=True, text=True).stdout
    head, rest = text.split(begin)
    _, tail = rest.split(end)
    wanted = head + begin + generated + end + tail
    if args.write:
        if wanted != text:
            temporary = args.file.with_name(args.file.name + ".tmp")
            temporary.write_text(wanted)
            temporary.replace(args.file)
        return 0
    if wanted != text:
        print(f"doc-section: the '{args.name}' section of {args.file} is not what "
              f"`{' '.join(command)}` prints; run scripts/doc-section.py --write "
              f"{args.file} {args.name} -- {' '.join(command)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
