#!/usr/bin/env python3
"""Checks the layering: a layer's files include only its own layer and the layers it declares.

A layer is the static library that a folder's CMakeLists.txt creates with
`pensight_add_layer(NAME NAMESPACE NS... [DEPENDS LAYER...])`; it owns every file under that folder
but those under a deeper folder with a layer of its own. Its code is in the namespaces NAMESPACE
lists: every `namespace pensight... {` that opens at the start of a line names one of them or its
`::detail`. Each `#include "..."` of a layer's .h/.hpp/.cpp/.cu/.cuh
file that names a file of the tree (from the root, else from the includer's folder; generated
headers name none and are skipped) must name a file of the includer's layer or of one in the
closure of its DEPENDS: never apps/, tests/ or another folder outside the layers, and a private
header (in a layer's internal/ folder, or *_detail.h) only from its own layer. DEPENDS names
layers only (third-party libraries go to target_link_libraries), without a cycle. Exit status 1
when a rule is broken. --graph prints the layers as Mermaid; --check-doc/--write-doc check or
rewrite that graph between the layers markers of a Markdown file (docs/architecture.md).
"""
import argparse
import os
import re
import sys
from collections import namedtuple
from pathlib import Path

SOURCES = {".h", ".hpp", ".cpp", ".cu", ".cuh"}
SKIP_DIRS = {".git", ".cache", "node_modules", "third_party"}
FIXTURES = "tests/layering/fixtures"
BEGIN = "<!-- layers:begin (scripts/check-layers.py --write-doc) -->"
END = "<!-- layers:end -->"
HEADING = "## Layers and CMake targets"
LAYER_CALL = re.compile(r"\bpensight_add_layer\s*\(([^)]*)\)")
INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"')
NAMESPACE_OPEN = re.compile(r"^namespace (pensight[\w:]*) \{")
KEYWORDS = ("NAMESPACE", "DEPENDS")
Layer = namedtuple("Layer", "name folder depends namespaces cmake line")


def walk(root):
    """Yields the paths (relative to root, as POSIX strings) of the files the check reads."""
    for top, dirs, files in os.walk(root):
        prefix = "" if Path(top) == root else Path(top).relative_to(root).as_posix() + "/"
        dirs[:] = sorted(d for d in dirs if not (d in SKIP_DIRS or d.startswith("build")
                                                 or prefix + d == FIXTURES))
        yield from (prefix + f for f in sorted(files))


def strip_comments(text):
    """CMake comments (#[[...]] and # to the end of the line) blanked, line numbers kept."""
    text = re.sub(r"#\[(=*)\[.*?\]\1\]", lambda m: "\n" * m.group(0).count("\n"), text,
                  flags=re.S)
    return re.sub(r"#[^\n]*", "", text)


def find_layers(root, files):
    layers = {}
    for rel in (f for f in files if Path(f).name == "CMakeLists.txt"):
        text = strip_comments((root / rel).read_text(errors="replace"))
        for m in LAYER_CALL.finditer(text):
            args = [a.strip('"') for a in m.group(1).split()]
            line = text.count("\n", 0, m.start()) + 1
            layers[args[0]] = Layer(args[0], Path(rel).parent.as_posix(),
                                    keyword_values(args, "DEPENDS"),
                                    keyword_values(args, "NAMESPACE"), rel, line)
    return layers


def keyword_values(args, keyword):
    """The arguments after `keyword` up to the next keyword."""
    if keyword not in args:
        return []
    values = args[args.index(keyword) + 1:]
    ends = [i for i, a in enumerate(values) if a in KEYWORDS]
    return values[:ends[0]] if ends else values


def owner(rel, by_folder):
    """The layer owning the file rel: the one of its deepest folder that declares one."""
    return next((by_folder[f.as_posix()] for f in Path(rel).parents if f.as_posix() in by_folder),
                None)


def closure(layer, layers):
    seen, todo = {layer.name}, list(layer.depends)
    while todo:
        name = todo.pop()
        if name in layers and name not in seen:
            seen.add(name)
            todo.extend(layers[name].depends)
    return seen


def cycle_from(path, layers):
    """A DEPENDS path from path[-1] back to path[0] (path extended by it), or None."""
    for dep in (d for d in layers[path[-1]].depends if d in layers):
        found = path + [dep] if dep == path[0] else None
        if not found and dep not in path:
            found = cycle_from(path + [dep], layers)
        if found:
            return found
    return None


def graph_errors(layers):
    errors, cycles = [], set()
    for layer in sorted(layers.values()):
        errors += [f'{layer.cmake}:{layer.line}: {layer.name} DEPENDS on "{dep}", which is not a '
                   "layer; link third-party libraries with target_link_libraries"
                   for dep in layer.depends if dep not in layers]
        cycle = cycle_from([layer.name], layers)
        if cycle and frozenset(cycle) not in cycles:
            cycles.add(frozenset(cycle))
            errors.append(f"{layer.cmake}:{layer.line}: layer dependency cycle: "
                          + " -> ".join(cycle))
    return errors


def resolve(rel, name, in_tree):
    """The file of the tree `#include "name"` in the file rel names: from the root, else rel's."""
    paths = (os.path.normpath(os.path.join(base, name)) for base in ("", Path(rel).parent))
    return next((p for p in paths if p in in_tree), None)


def include_error(rel, line, name, target, layer, layers, by_folder):
    other = owner(target, by_folder)
    if other is None:
        folder = target.split("/")[0] if "/" in target else "."
        return (f'{rel}:{line}: includes "{name}" from {folder}/, which is not a library layer; '
                "a layer may include only layers it declares")
    inside = Path(os.path.relpath(target, other.folder)).parts[:-1]
    if other.name != layer.name and ("internal" in inside or target.endswith("_detail.h")):
        return f'{rel}:{line}: includes "{name}", which is private to layer {other.name}'
    if other.name not in closure(layer, layers):
        deps = " ".join(layer.depends) or "none"
        return (f'{rel}:{line}: includes "{name}" of layer {other.name}, which {layer.name} does '
                f"not declare (DEPENDS: {deps}; from {layer.cmake}); declare it there if the "
                "dependency is meant, or move the code to a lower layer")
    return None


def namespace_error(rel, line, name, layer):
    allowed = layer.namespaces + [ns + "::detail" for ns in layer.namespaces]
    if name in allowed:
        return None
    return (f"{rel}:{line}: namespace {name} is not one of layer {layer.name}'s "
            f"(NAMESPACE {' '.join(layer.namespaces)} in {layer.cmake}); namespaces follow folders")


def check_sources(root, files, layers):
    by_folder = {layer.folder: layer for layer in layers.values()}
    in_tree, errors, scanned, checked = set(files), [], 0, 0
    errors += [f"{l.cmake}:{l.line}: layer {l.name} declares no NAMESPACE"
               for l in layers.values() if not l.namespaces]
    for rel in files:
        layer = owner(rel, by_folder)
        if layer is None or Path(rel).suffix not in SOURCES:
            continue
        scanned += 1
        lines = (root / rel).read_text(errors="replace").splitlines()
        for number, text in enumerate(lines, 1):
            m = INCLUDE.match(text)
            target = m and resolve(rel, m.group(1), in_tree)
            if target:
                checked += 1
                error = include_error(rel, number, m.group(1), target, layer, layers, by_folder)
                errors += [error] if error else []
            ns = NAMESPACE_OPEN.match(text)
            if ns and layer.namespaces:
                error = namespace_error(rel, number, ns.group(1), layer)
                errors += [error] if error else []
    return errors, scanned, checked


def graph(layers):
    lines = ["```mermaid", "flowchart TD",
             "  %% an arrow runs from a layer to a layer it DEPENDS on; the lowest at the bottom"]
    for layer in sorted(layers.values(), key=lambda x: x.name):
        folder = "" if layer.folder == "." else layer.folder
        lines.append(f'  {layer.name}["{layer.name}<br/>{folder}/"]')
    edges = sorted((l.name, d) for l in layers.values() for d in l.depends if d in layers)
    lines += [f"  {user} --> {dep}" for user, dep in edges]
    return "\n".join(lines + ["```"])


def doc_split(lines):
    """(lines up to the begin marker, the block between the markers, lines from the end marker)."""
    if BEGIN not in lines or END not in lines:
        return None
    begin, end = lines.index(BEGIN) + 1, lines.index(END)
    return lines[:begin], "\n".join(lines[begin:end]).strip("\n"), lines[end:]


def write_doc(path, block):
    lines = Path(path).read_text().split("\n")
    if not doc_split(lines) and HEADING in lines:  # first time: the block goes under the heading
        at = lines.index(HEADING) + 1
        lines[at:at] = ["", BEGIN, END]
    parts = doc_split(lines) or sys.exit(f"{path}: no layers markers and no '{HEADING}'")
    Path(path).write_text("\n".join(parts[0] + [block] + parts[2]))


def check_doc(path, block):
    parts = doc_split(Path(path).read_text().split("\n") if Path(path).is_file() else [])
    if parts and parts[1] == block:
        return []
    return [f"{path}: the layer graph between its layers markers is missing or out of date; run "
            "python3 scripts/check-layers.py --write-doc docs/architecture.md"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--root", default=Path(__file__).resolve().parent.parent, type=Path)
    parser.add_argument("--graph", action="store_true", help="print the Mermaid layer graph")
    parser.add_argument("--check-doc", metavar="FILE", help="FILE's layer graph must be current")
    parser.add_argument("--write-doc", metavar="FILE", help="rewrite FILE's layer graph")
    args = parser.parse_args()
    root = args.root.resolve()
    files = list(walk(root))
    layers = find_layers(root, files)
    if args.graph:
        print(graph(layers))
    if args.write_doc:
        write_doc(args.write_doc, graph(layers))
    if args.graph or args.write_doc:
        return 0
    errors = graph_errors(layers)
    source_errors, scanned, checked = check_sources(root, files, layers)
    errors += source_errors + (check_doc(args.check_doc, graph(layers)) if args.check_doc else [])
    print("\n".join(errors + [""]), end="")
    print(f"layers: {len(layers)} layers, {scanned} files, {checked} includes checked, "
          f"{len(errors)} errors")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
