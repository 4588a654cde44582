#!/usr/bin/env python3
"""Lists the C++ functions longer than a limit, from the line of their name to
their closing brace.

    tools/function-lengths.py [--limit 80] [paths...]   (default: src include tools)

Exits 1 if any function is longer than the limit. A function is a brace block
opened at namespace or class scope after a parameter list; lambdas and local
classes count as part of the function that holds them. Comments, strings and
preprocessor lines are read as blanks first, so braces inside them are ignored.
"""
import argparse
import pathlib
import re
import sys

SOURCE_SUFFIXES = {".cc", ".h", ".cpp", ".hpp", ".h.in"}
RAW_STRING = re.compile(r'R"([^(\s]*)\((?:.|\n)*?\)\1"')
TOKENS = re.compile(
    r'//[^\n]*|/\*(?:.|\n)*?\*/|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'')


def blanked(text):
    """The text with comments, strings and preprocessor lines as spaces,
    newlines kept so that offsets still give line numbers."""
    def blank(match):
        return re.sub(r"[^\n]", " ", match.group(0))
    text = RAW_STRING.sub(blank, text)
    text = TOKENS.sub(blank, text)
    lines = text.split("\n")
    in_directive = False
    for i, line in enumerate(lines):
        if in_directive or line.lstrip().startswith("#"):
            in_directive = line.rstrip().endswith("\\")
            lines[i] = " " * len(line)
    return "\n".join(lines)


def scope_kind(head):
    """What a brace opened after `head` (the text since the last ; { or })
    begins: a namespace, a class, a function or anything else."""
    words = head.split()
    if not words:
        return "other"
    if "namespace" in words or head.lstrip().startswith("extern"):
        return "namespace"
    if re.search(r"\b(class|struct|union|enum)\b", head) and "(" not in head.split("{")[0].split(":")[0]:
        return "class"
    if re.search(r"\)\s*(const|noexcept|override|final|mutable|volatile|&|&&|\s|->[^{]*|"
                 r"try|:.*)*$", head, re.S) and not re.search(r"(^|[^=!<>])=\s*[^=]", head.split("(")[0]):
        return "function"
    return "other"


def functions(path):
    """(first line, last line, name) of every function of one file."""
    text = blanked(path.read_text(errors="replace"))
    line_of = [0] * (len(text) + 1)
    line = 1
    for i, ch in enumerate(text):
        line_of[i] = line
        if ch == "\n":
            line += 1
    stack = []  # (kind, start offset of head)
    head_start = 0
    found = []
    i = 0
    while i < len(text):
        ch = text[i]
        if ch == ";" :
            head_start = i + 1
        elif ch == "{":
            head = text[head_start:i]
            kind = scope_kind(head) if all(k in ("namespace", "class") for k, _ in stack) else "inner"
            member_init = (kind == "function" and re.search(r"\)\s*:", head)
                           and re.search(r"[\w>]\s*$", head))
            if member_init:
                # A member initialised with braces: skip to its closing brace.
                depth = 0
                while i < len(text):
                    if text[i] == "{":
                        depth += 1
                    elif text[i] == "}":
                        depth -= 1
                        if depth == 0:
                            break
                    i += 1
            else:
                start = head_start + len(head) - len(head.lstrip())
                stack.append((kind, start))
                head_start = i + 1
        elif ch == "}":
            if stack:
                kind, start = stack.pop()
                if kind == "function":
                    name = re.findall(r"([\w:~<>]+)\s*\(", text[start:i])
                    found.append((line_of[start], line_of[i], name[0] if name else "?"))
            head_start = i + 1
        i += 1
    return found


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--limit", type=int, default=80)
    parser.add_argument("paths", nargs="*", default=["src", "include", "tools"])
    args = parser.parse_args()
    too_long = []
    for root in args.paths:
        root = pathlib.Path(root)
        files = [root] if root.is_file() else sorted(
            p for p in root.rglob("*") if p.is_file() and "".join(p.suffixes[-2:]) in SOURCE_SUFFIXES
            or p.suffix in SOURCE_SUFFIXES)
        for path in files:
            for first, last, name in functions(path):
                length = last - first + 1
                if length > args.limit:
                    too_long.append((length, f"{path}:{first}", name))
    for length, where, name in sorted(too_long, reverse=True):
        print(f"{length:5d} lines  {where}  {name}")
    if too_long:
        print(f"{len(too_long)} functions longer than {args.limit} lines", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
