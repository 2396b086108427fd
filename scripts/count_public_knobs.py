#!/usr/bin/env python3
"""Lists the leaf fields (knobs) reachable from a public params struct, read from the public
headers (*/include/**/*.h): a field whose type is another params struct is followed into it.

  scripts/count_public_knobs.py LocalizerParams [--root .] [--count]

A struct's fields are its public data members (static members, functions, type declarations
and private members, reached only through an accessor, left out); std::optional<T> counts as
T. The count is what the docs quote as the public surface; it reads source text, so a member declared through a macro would be missed (none is).
"""
import argparse
import glob
import os
import re
import sys

# Value types with fields of their own that are one knob to a user (a camera's intrinsics).
OPAQUE = {"PinholeIntrinsics"}


def strip_comments(text):
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    return re.sub(r"//[^\n]*", "", text)


def struct_bodies(text):
    """{name: the body's top-level text, function bodies replaced by ';'}."""
    bodies = {}
    for m in re.finditer(r"\bstruct\s+(\w+)\s*(?:final\s*)?\{", text):
        depth, j = 1, m.end()
        while depth > 0 and j < len(text):
            depth += {"{": 1, "}": -1}.get(text[j], 0)
            j += 1
        top, depth = [], 0
        for ch in text[m.end():j - 1]:
            if ch == "{":
                depth += 1
            elif ch == "}":
                depth -= 1
                if depth == 0:
                    top.append(";")
            elif depth == 0:
                top.append(ch)
        bodies[m.group(1)] = "".join(top)
    return bodies


def fields(body):
    out = []
    public = True  # a struct's members are public until an access specifier says otherwise
    for statement in body.split(";"):
        s = " ".join(statement.split())
        while True:
            m = re.match(r"^(public|private|protected):\s*", s)
            if not m:
                break
            public = m.group(1) == "public"
            s = s[m.end():]
        if not public:
            continue
        if not s or s.startswith(("static", "using", "friend", "template", "enum", "typedef",
                                  "struct", "class")):
            continue
        s = re.sub(r"\s*=.*$", "", s)
        if "(" in s:  # a function declaration
            continue
        m = re.match(r"(.+?)\s+(\w+)(\[[^\]]*\])?$", s)
        if not m:
            continue
        type_, names = m.group(1).strip(), [m.group(2)]
        if "," in type_ and "<" not in type_:  # int a, b, c
            head, *rest = [p.strip() for p in s.split(",")]
            type_, first = head.rsplit(" ", 1)
            names = [first] + rest
        out += [(type_, n) for n in names]
    return out


def leaves(structs, name, prefix=""):
    out = []
    for type_, field in fields(structs[name]):
        base = re.sub(r"^std::optional<(.*)>$", r"\1", type_)
        base = re.sub(r".*::", "", base).strip()
        if base in structs and base not in OPAQUE:
            out += leaves(structs, base, prefix + field + ".")
        else:
            out.append((prefix + field, type_))
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("struct")
    parser.add_argument("--root", default=os.path.join(os.path.dirname(__file__), ".."))
    parser.add_argument("--count", action="store_true", help="print the count only")
    args = parser.parse_args()
    structs = {}
    for path in sorted(glob.glob(os.path.join(args.root, "*/include/**/*.h"), recursive=True)):
        with open(path, encoding="utf-8") as f:
            structs.update(struct_bodies(strip_comments(f.read())))
    if args.struct not in structs:
        sys.exit(f"count_public_knobs: no struct {args.struct} in the public headers")
    found = leaves(structs, args.struct)
    if args.count:
        print(len(found))
        return
    for path, type_ in found:
        print(f"{path}  ({type_})")
    print(f"{len(found)} fields reachable from {args.struct}")


if __name__ == "__main__":
    main()
