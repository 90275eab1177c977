#!/usr/bin/env bash
# Citations that a reader can open: every repository path that the sources (code, comments,
# scripts) and the docs cite exists (docs/errata.md, integrate/laws.h, a Markdown link), and
# nothing cites what a reader of the repository cannot open: an issue number ("issue 15",
# "issue #20", "#15's"), or a file outside it (design.md, cli-contract.md, style.md, the shared
# folder beside the repository). A generated doc (one that says "do not edit") is held to the
# last two through its generator, whose source is checked: its text changes when it is
# regenerated, and a line its generator no longer writes is listed as a note, not a failure.
# Usage: citations_test.sh SOURCE_DIR
set -u
cd "$1" || exit 1
python3 - <<'EOF'
import os, re, subprocess, sys

MODULES = ("bench", "cli", "cmake", "docs", "examples", "export", "fuzz", "integrate", "models", "rasterizer",
           "reference", "reports", "scene", "scripts", "serve", "shapes", "tables", "tests", "util")
TEXT = (".cpp", ".h", ".js", ".html", ".py", ".sh", ".md", ".txt", ".cmake", ".in", ".json", ".yaml", ".dict")
SKIP_DIRS = {".git", "node_modules", "corpus"}
THIS = os.path.join("tests", "citations_test.sh")

# A path into the repository: MODULE/rest, not inside a longer path (build/cli/ganzfeld is a build output).
PATH = re.compile(r"(?<![\w./-])((?:%s)/[\w./-]*[\w/])" % "|".join(MODULES))
LINK = re.compile(r"\]\(([^)#\s]+)(?:#[^)]*)?\)")  # a Markdown link's target
ISSUE = re.compile(r"\b[Ii]ssues?[\s#-]*\d+|\(#\d+|#\d+'s|#\d+\)")
OUTSIDE = re.compile(r"(?<![\w/-])(?:design|cli-contract|style)\.md\b|\.\./shared\b|/work/shared\b")


def files():
    for top in ["."]:
        for root, dirs, names in os.walk(top):
            dirs[:] = [d for d in dirs if d not in SKIP_DIRS and not d.startswith("build")]
            for name in names:
                path = os.path.normpath(os.path.join(root, name))
                if (name.endswith(TEXT) or name in ("CMakeLists.txt",) or root.endswith("scripts")) \
                        and path != THIS:
                    yield path


def exists(target):
    """The file or folder, or a stem of files (reports/verify for reports/verify.{h,cpp})."""
    target = target.rstrip("/")
    if os.path.exists(target):
        return True
    folder, stem = os.path.split(target)
    return os.path.isdir(folder or ".") and any(name.startswith(stem + c) for name in os.listdir(folder or ".")
                                                for c in ".-_")


def ignored(paths):
    """The paths git ignores: what a command writes (examples/three/tables/), not a citation."""
    try:
        run = subprocess.run(["git", "check-ignore", "--no-index", "--stdin"], input="\n".join(paths),
                             capture_output=True, text=True)
    except OSError:
        return set()
    return set(run.stdout.split())


failures, notes = [], []
missing = []  # (where, what, target, the folder of the citing file)
for path in sorted(files()):
    try:
        text = open(path, encoding="utf-8").read()
    except UnicodeDecodeError:
        continue
    generated = path.endswith(".md") and "do not edit" in text[:600].lower()
    for number, line in enumerate(text.splitlines(), 1):
        where = f"{path}:{number}"
        for match in PATH.finditer(line):
            target, before, after = match.group(1), line[:match.start()], line[match.end():]
            if after.startswith(("*", "-*")) or re.search(r"/[A-Z][A-Z0-9_]*(/|\.|$)", target):
                continue  # a pattern or a placeholder (docs/tradeoff-*.png, fuzz/corpus/TARGET/)
            if before.endswith("'") or re.search(r"(--out|-o|--markdown|--plot|>)\s+$", before):
                continue  # a quoted value in an example, or where a command writes
            if not exists(target):
                missing.append((where, "cites", target, os.path.dirname(path)))
        if path.endswith(".md"):
            for target in LINK.findall(line):
                if re.match(r"[a-z]+:", target):
                    continue  # a URL
                if not exists(os.path.join(os.path.dirname(path), target)):
                    missing.append((where, "links", target, os.path.dirname(path)))
        found = [f"cites an issue number ({f.strip()})" for f in ISSUE.findall(line)] + \
                [f"cites {f}, which is outside the repository" for f in OUTSIDE.findall(line)]
        (notes if generated else failures).extend(f"{where}: {f}" for f in found)

outputs = ignored([t for _, _, t, _ in missing] + [os.path.join(d, t) for _, _, t, d in missing])
failures += [f"{where}: {what} {target}, which does not exist" for where, what, target, folder in missing
             if target not in outputs and os.path.join(folder, target) not in outputs]
for note in notes:
    print("note (generated; awaits regeneration):", note)
for failure in failures:
    print("FAIL:", failure)
print(f"citations_test: {len(failures)} rotted citation(s)")
sys.exit(1 if failures else 0)
EOF
