#!/usr/bin/python3
"""The user guide (docs/*.md, docs/algorithms/*.md) as HTML pages, for the
Help button of each Processing dialog and GeoStation > Help.

    docs_html.py SOURCE_DOCS_DIR OUTPUT_DIR

Each Markdown page becomes a page of the same name with .html; links between
pages follow (x.md -> x.html, x.md#part -> x.html#part); docs/images is copied.
Needs Debian's python3-markdown (scripts/setup-debian.sh installs it). Writes
into a fresh folder beside OUTPUT_DIR and swaps it in, so a failed run leaves
the previous pages as they were.
"""
import html
import os
import re
import shutil
import sys

import markdown

PAGE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>{title} - GeoStation</title>
<style>
body {{ font-family: sans-serif; max-width: 60em; margin: 1em auto; padding: 0 1em; line-height: 1.45; }}
table {{ border-collapse: collapse; margin: 0.5em 0; }}
th, td {{ border: 1px solid #bbb; padding: 0.2em 0.5em; vertical-align: top; text-align: left; }}
code, pre {{ background: #f3f3f3; }}
pre {{ padding: 0.5em; overflow-x: auto; }}
img {{ max-width: 100%; }}
nav {{ font-size: 90%; margin-bottom: 1em; }}
</style>
</head>
<body>
<nav>{nav}</nav>
{body}
</body>
</html>
"""

LINK = re.compile(r'href="(?![a-z]+:)([^"#]*?)\.md(#[^"]*)?"')


def convert(source, target, depth):
    with open(source, encoding="utf-8") as f:
        text = f.read()
    title_match = re.search(r"^# (.+)$", text, re.M)
    title = re.sub(r"[`*]", "", title_match.group(1)) if title_match else os.path.basename(source)
    body = markdown.markdown(text, extensions=["tables", "fenced_code", "toc"], output_format="html5")
    body = LINK.sub(lambda m: 'href="{}.html{}"'.format(m.group(1), m.group(2) or ""), body)
    up = "../" * depth
    nav = '<a href="{0}getting-started.html">Getting started</a> · <a href="{0}algorithms/README.html">Algorithms</a> · ' \
          '<a href="{0}glossary.html">Glossary</a> · <a href="{0}troubleshooting.html">Troubleshooting</a>'.format(up)
    with open(target, "w", encoding="utf-8") as f:
        f.write(PAGE.format(title=html.escape(title), nav=nav, body=body))


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: docs_html.py SOURCE_DOCS_DIR OUTPUT_DIR")
    source, output = (os.path.abspath(p) for p in sys.argv[1:])
    staging = output + ".new"
    shutil.rmtree(staging, ignore_errors=True)
    pages = 0
    for folder, _, files in os.walk(source):
        relative = os.path.relpath(folder, source)
        depth = 0 if relative == "." else relative.count(os.sep) + 1
        os.makedirs(os.path.join(staging, relative), exist_ok=True)
        for name in sorted(files):
            if name.endswith(".md"):
                convert(os.path.join(folder, name), os.path.join(staging, relative, name[:-3] + ".html"), depth)
                pages += 1
            elif name.endswith((".png", ".svg", ".jpg")):
                shutil.copy2(os.path.join(folder, name), os.path.join(staging, relative, name))
    shutil.rmtree(output, ignore_errors=True)
    os.replace(staging, output)
    print("docs_html.py: {} pages in {}".format(pages, output))


if __name__ == "__main__":
    main()
