#!/usr/bin/env bash
# Every generated doc names the command that regenerates it, and that command exists: a
# `ganzfeld SUBCOMMAND` whose --help lists each flag the doc quotes, or a script of the
# repository. A doc assembled from generated sections (docs/reliability*.md, docs/three.md) names
# one per section. Regenerating takes from seconds to hours, so only the quick ones are also
# compared with what their command writes now: docs/errata.md (verify_test),
# docs/plausibility.md (plausibility_test), docs/model-parameters.md (cli_test).
# Usage: generated_docs_test.sh PATH/TO/ganzfeld SOURCE_DIR
set -u
G="$1"
cd "$2" || exit 1
python3 - "$G" <<'EOF'
import os, re, subprocess, sys

ganzfeld = sys.argv[1]
DOCS = ["code-health.md", "errata.md", "fetch-budget.md", "model-parameters.md", "performance.md", "plausibility.md",
        "realtime.md",
        "reliability.md", "reliability-extremes.md", "reliability-genz.md",
        "serve-load.md", "three.md", "tradeoff.md"]
STAMP = re.compile(r"[Gg]enerated (?:from [^`]*? )?by `?((?:ganzfeld|scripts/|tests/)[^`;(]*?)`?\s*(?:[;(]|on |$)",
                   re.MULTILINE)
failures = []


def check(doc, command):
    words = command.split()
    if words[0] == "ganzfeld":
        run = subprocess.run([ganzfeld, words[1], "--help"], capture_output=True, text=True)
        if run.returncode != 0:
            return f"{doc}: `{command}`: ganzfeld has no subcommand {words[1]}"
        missing = [w.split("=")[0] for w in words[2:] if w.startswith("--") and w.split("=")[0] not in run.stdout]
        if missing:
            return f"{doc}: `{command}`: `ganzfeld {words[1]}` has no flag {', '.join(missing)}"
    elif not os.access(words[0], os.X_OK):
        return f"{doc}: `{command}`: {words[0]} is not an executable of the repository"
    return None


for doc in DOCS:
    path = os.path.join("docs", doc)
    if not os.path.exists(path):
        failures.append(f"{path} is missing")
        continue
    text = open(path, encoding="utf-8").read()
    sections = re.findall(r"<!-- begin (\S+) -->(.*?)<!-- end \1 -->", text, re.DOTALL)
    parts = sections if sections else [("the document", text[:2000])]
    for name, part in parts:
        commands = STAMP.findall(part)
        if not commands:
            failures.append(f"{path} ({name}) names no command that generated it")
        for command in commands:
            failure = check(path, command.strip())
            if failure:
                failures.append(failure)
            else:
                print(f"ok: {path} ({name}): {command.strip()}")

for failure in failures:
    print("FAIL:", failure)
print(f"generated_docs_test: {len(failures)} failure(s)")
sys.exit(1 if failures else 0)
EOF
