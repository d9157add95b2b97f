"""docs/architecture.md's table of core's modules lists, in its "uses"
column, exactly the modules each one declares in core/CMakeLists.txt (the
build writes them to core-modules.txt: "module: used used ..."), in the
build's order.

    check_module_table.py docs/architecture.md build/core-modules.txt
"""
import re
import sys


def declared(path):
    modules = {}
    for line in open(path):
        if ":" in line:
            name, uses = line.split(":", 1)
            modules[name.strip()] = set(uses.split())
    return modules


def documented(path):
    modules = {}
    for line in open(path):
        m = re.match(r"^\| `([a-z]+)/` \|.*\| ([^|]*) \|\s*$", line)
        if m:
            uses = m.group(2).strip()
            modules[m.group(1)] = set() if uses in ("–", "-", "") else {u.strip() for u in uses.split(",")}
    return modules


def main():
    built, docs = declared(sys.argv[2]), documented(sys.argv[1])
    problems = []
    for name, uses in built.items():
        if name not in docs:
            problems.append("%s/ is a module of the build but not in the table" % name)
        elif docs[name] != uses:
            problems.append("%s/ uses %s in the build, the table says %s" % (name, ", ".join(sorted(uses)) or "nothing", ", ".join(sorted(docs[name])) or "nothing"))
    for name in docs:
        if name not in built:
            problems.append("%s/ is in the table but not a module of the build" % name)
    if list(docs) != [n for n in built if n in docs]:
        problems.append("the table's order %s is not the build's %s" % (", ".join(docs), ", ".join(built)))
    for p in problems:
        print(p)
    if problems:
        sys.exit(1)
    print("%d modules: the table says what the build declares" % len(built))


if __name__ == "__main__":
    main()
