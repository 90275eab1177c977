#!/usr/bin/env bash
# Library code names parameters, never a front end's flags (util/error.h: an InputError names a
# parameter, {"max_error", "0.5"}, and the command line spells it --max-error 0.5, a query
# max_error=0.5, a library file its key). So no string literal of the library modules (and of
# serve/, whose clients send queries) holds a flag (--name), except the words of commands the
# library writes on purpose: a literal that is a flag alone ("--max-error", the stamped
# `ganzfeld bake` line of a cache entry, scene/plan.cpp), the bake flags the table-scheme report
# labels its rows with (reports/schemes.cpp) and a command the service points its client to.
# Comments are not checked.
# Usage: library_messages_test.sh SOURCE_DIR
set -u
cd "$1" || exit 1
python3 - <<'EOF'
import pathlib, re, sys

MODULES = ["util", "models", "reference", "integrate", "tables", "scene", "export", "shapes", "reports",
           "rasterizer", "serve", "fit"]
# Literals that label rows or a plot with the `bake` flags they stand for (not messages).
LABELS = {("reports/schemes.cpp", '"--max-error "'), ("reports/schemes.cpp", '" --max-bytes "'),
          ("reports/schemes.cpp", '" --encoding unorm16"'), ("reports/schemes.cpp", '" --fetches "'),
          ("reports/schemes.cpp", '"today: cosines frame, linear.  max-error: what bake --max-error picks.  other lookup, half: the"'),
          ("serve/service.cpp", '"export-glsl --scene`)"')}
# Files that write a generated document whose text shows the commands that regenerate its figures.
DOCUMENT_WRITERS = {"fit/report.cpp"}
LITERAL = re.compile(r'"(?:[^"\\\n]|\\.)*"')
FLAG = re.compile(r"--[a-z]")
FLAG_ALONE = re.compile(r'^"--[a-z][a-z0-9-]*"$')

def code_of(line):
    """The line without its // comment (a // inside a literal stays)."""
    out, k, quote = [], 0, False
    while k < len(line):
        c = line[k]
        if quote:
            out.append(c)
            if c == "\\" and k + 1 < len(line):
                out.append(line[k + 1]); k += 1
            elif c == '"':
                quote = False
        elif c == '"':
            quote = True; out.append(c)
        elif line.startswith("//", k):
            break
        else:
            out.append(c)
        k += 1
    return "".join(out)

failures = 0
for module in MODULES:
    for path in sorted(pathlib.Path(module).glob("*")):
        if path.suffix not in (".h", ".cpp"):
            continue
        for number, line in enumerate(path.read_text().splitlines(), 1):
            for literal in LITERAL.findall(code_of(line)):
                if (not FLAG.search(literal) or FLAG_ALONE.match(literal) or (str(path), literal) in LABELS
                        or str(path) in DOCUMENT_WRITERS):
                    continue
                print(f"FAIL: {path}:{number}: a library literal names a flag: {literal}")
                failures += 1
print(f"library_messages_test: {failures} literal(s) naming a flag")
sys.exit(1 if failures else 0)
EOF
