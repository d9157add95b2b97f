#!/usr/bin/python3
"""The changelog field of the plugins' metadata.txt from CHANGELOG.md: each
dated section ("## 2026-12-01") with the bold titles of its entries, newest
first, in the indented form QGIS's metadata parser continues a field with.

    metadata_changelog.py CHANGELOG.md
"""
import re
import sys


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: metadata_changelog.py CHANGELOG.md")
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
        sys.exit("metadata_changelog.py: no dated section in " + sys.argv[1])
    # the first line follows "changelog=", the others are continuation lines
    print("\n    ".join(lines[:60]))


if __name__ == "__main__":
    main()
