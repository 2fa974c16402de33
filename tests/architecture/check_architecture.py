#!/usr/bin/env python3
"""Holds the code to docs/architecture.json's rules, from the includes and the text of the code.

- "never": [A, B, why]: no file of part A includes a file of part B (a file belongs to the part
  whose listed path is the longest prefix of its path).
- "components_known_by_role": no dynamic_cast anywhere in src/ and apps/, and no comparison of a
  string with a component's registered name outside the component's own module and the registry.
  The names come from `starnav params --json` (given as the second argument).

Usage: check_architecture.py REPO_ROOT STARNAV_BINARY. Prints each broken rule on one line; exit 1
when any is broken.
"""
import json
import os
import re
import subprocess
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def source_files(root, top):
    for base, _, files in os.walk(os.path.join(root, top)):
        for f in files:
            if f.endswith((".cpp", ".hpp", ".h", ".cc")):
                yield os.path.relpath(os.path.join(base, f), root)


def part_of(path, parts):
    best, best_len = None, -1
    for name, part in parts.items():
        for p in part["is"]:
            hit = path == p or (p.endswith("/") and path.startswith(p))
            if hit and len(p) > best_len:
                best, best_len = name, len(p)
    return best


def resolve_include(root, including, target):
    # starnav's headers are included from src/ ("starnav/..."); the CLI's own beside the file.
    for candidate in (os.path.join("src", target), os.path.join(os.path.dirname(including), target)):
        if os.path.isfile(os.path.join(root, candidate)):
            return os.path.normpath(candidate)
    return None


def strip_comments(text):
    # Comments out, their lines kept (so line numbers stay true).
    text = re.sub(r"/\*.*?\*/", lambda m: "\n" * m.group(0).count("\n"), text, flags=re.S)
    return re.sub(r"//[^\n]*", "", text)


def main():
    root, binary = sys.argv[1], sys.argv[2]
    with open(os.path.join(root, "docs", "architecture.json")) as f:
        board = json.load(f)
    parts = board["parts"]
    broken = []
    files = sorted(set(source_files(root, "src")) | set(source_files(root, "apps")))
    texts = {}
    for path in files:
        with open(os.path.join(root, path), encoding="utf-8", errors="replace") as f:
            texts[path] = f.read()

    for a, b, why in board["never"]:
        for path in files:
            if part_of(path, parts) != a:
                continue
            for target in INCLUDE.findall(texts[path]):
                included = resolve_include(root, path, target)
                if included and part_of(included, parts) == b:
                    broken.append(f"{path}: includes {included} ({a} -> {b}: {why})")

    components = json.loads(subprocess.run([binary, "params", "--json"], check=True, capture_output=True, text=True).stdout)
    # A component's module: where its role's implementations live.
    role_modules = {
        "global_planner": ("src/starnav/plan/", "src/starnav/terrain/"),
        "local_controller": ("src/starnav/control/",), "goal_checker": ("src/starnav/control/",),
        "progress_checker": ("src/starnav/control/",), "recovery": ("src/starnav/control/",),
        "localizer": ("src/starnav/estimate/",), "slam": ("src/starnav/slam/",), "scan_matcher": ("src/starnav/slam/",),
        "scan_matcher_3d": ("src/starnav/cloud/",), "costmap_layer": ("src/starnav/costmap/",),
    }
    module_of = {}
    for c in components:
        if c.get("role") in role_modules:
            module_of.setdefault(c["name"], set()).update(role_modules[c["role"]])
    unknown_roles = sorted({c.get("role") for c in components} - set(role_modules) - {"navigation"})
    if unknown_roles:
        broken.append("check_architecture.py: roles without a module here: " + ", ".join(unknown_roles))
    names = sorted(module_of)
    # A comparison whose other side names a choice of component (a planner, a controller, ...,
    # or a name): words such as "odometry" compared with a key or a pose source are not.
    choice = re.compile(r"planner|controller|localizer|matcher|slam|layer|checker|recover|name", re.I)
    operand = r"[\w\.\->\[\]]+(?:\(\))?"
    for path in files:
        code = strip_comments(texts[path])
        if "dynamic_cast" in code or "dynamic_pointer_cast" in code:
            broken.append(f"{path}: dynamic_cast (components are known through their role)")
        if path.startswith("src/starnav/registry/"):
            continue
        for name in names:
            if any(path.startswith(m) for m in module_of[name]):
                continue
            literal = '"' + re.escape(name) + '"'
            pattern = "(" + operand + r")\s*(?:==|!=)\s*" + literal + "|" + literal + r"\s*(?:==|!=)\s*(" + operand + ")"
            for m in re.finditer(pattern, code):
                side = m.group(1) or m.group(2)
                if not choice.search(side):
                    continue
                line = code.count("\n", 0, m.start()) + 1
                broken.append(f"{path}:{line}: compares {side} with the component name '{name}' (known through its role and capabilities)")
    for b in broken:
        print(b)
    print(f"architecture: {len(board['never'])} never rules over {len(files)} files, {len(names)} component names: "
          f"{len(broken)} broken")
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
