#!/usr/bin/python3
"""The changelog field of the plugins' metadata.txt from CHANGELOG.md: each
version's section ("## 0.1.0 — 2026-12-03", or "## Unreleased") with the bold
titles of its entries, newest first, in the indented form QGIS's metadata
parser continues a field with.

    metadata_changelog.py CHANGELOG.md [VERSION]

With VERSION (CMakeLists.txt's), the newest section must be that version's
or "Unreleased": a release whose changelog says another version fails.
"""
import re
import sys


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit("usage: metadata_changelog.py CHANGELOG.md [VERSION]")
    version = sys.argv[2] if len(sys.argv) == 3 else None
    lines = []
    with open(sys.argv[1], encoding="utf-8") as f:
        for line in f:
            section = re.match(r"^## (.+)$", line)
            if section:
                lines.append(section.group(1).strip() + ":")
                continue
            entry = re.match(r"^- \*\*(.+?)\*\*", line)
            if entry and lines:
                # plain text: no Markdown code marks; "%" would start an interpolation in QGIS's parser
                lines.append("    - " + entry.group(1).rstrip(":. ").replace("`", "").replace("%", " per cent"))
    if not lines:
        sys.exit("metadata_changelog.py: no version section in " + sys.argv[1])
    newest = lines[0][:-1]
    if version and newest != "Unreleased" and newest.split()[0] != version:
        sys.exit("metadata_changelog.py: the newest section of %s is \"%s\", not version %s (CMakeLists.txt) or \"Unreleased\"" % (sys.argv[1], newest, version))
    # the first line follows "changelog=", the others are continuation lines
    print("\n    ".join(lines[:60]))


if __name__ == "__main__":
    main()
