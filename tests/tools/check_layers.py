#!/usr/bin/python3
"""fe_server's layer rule, as its source README states it, checked on the code.

fe_server/src/README.md lists the folders in a table, one layer per row: a
file may include headers of its own folder and of the folders above it in
that table, never of one below (and never by a relative "../" path, which
would pass the rule unseen). This reads the order from the README (so the
check follows the document, not a copy of it) and every
`#include "folder/..."` in fe_server/src/<folder>/, and fails naming each
include that goes downwards, or a folder the table does not list.

usage: check_layers.py SOURCE_ROOT
"""
import pathlib
import re
import sys


def layers(readme: pathlib.Path) -> list:
    order = []
    for line in readme.read_text(encoding="utf-8").splitlines():
        m = re.match(r"\|\s*`([a-z_]+)/`\s*\|", line)
        if m:
            order.append(m.group(1))
    return order


def main() -> int:
    src = pathlib.Path(sys.argv[1]) / "fe_server" / "src"
    order = layers(src / "README.md")
    if len(order) < 2:
        print(f"{src / 'README.md'}: no layer table found", file=sys.stderr)
        return 1
    rank = {name: i for i, name in enumerate(order)}
    folders = sorted(p.name for p in src.iterdir() if p.is_dir())
    errors = [f"{src / f}/: a folder the layer table in {src / 'README.md'} does not list"
              for f in folders if f not in rank]
    checked = 0
    for folder in folders:
        if folder not in rank:
            continue
        for path in sorted((src / folder).glob("*.[ch]pp")):
            for no, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
                if re.match(r'\s*#\s*include\s+[<"]\.\./', line):  # would pass the rule unseen
                    errors.append(f"{path}:{no}: a relative include; name the layer (\"loads/...\")")
                    continue
                m = re.match(r'\s*#\s*include\s+"([a-z_]+)/', line)
                if not m or m.group(1) not in rank:
                    continue  # another library's header (config/, socketlib/, ...)
                checked += 1
                to = m.group(1)
                if rank[to] > rank[folder]:
                    errors.append(f"{path}:{no}: {folder}/ includes {to}/, a layer below it "
                                  f"(order: {', '.join(order)})")
    for e in errors:
        print(e, file=sys.stderr)
    print(f"{checked} includes across {len(order)} layers checked; {len(errors)} against the rule")
    return 1 if errors or checked == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
