#!/usr/bin/env python3
"""Lists the C++ functions longer than a limit and fails on those that do not say why.

A function is long when its body, from the line of its opening brace to the line of its closing
brace, has more than --limit lines (default 100; docs/development.md's rule: no function over 100
lines without a comment that says why). A long function is accepted when the comment lines
directly above it (above its signature, or above its `template <...>` line) hold the marker
`// long:` followed by the reason, e.g.

    // long: one pass over the contact rows; split, the steps would share eight locals
    void CapacitanceContact::update(...) {

Prints `path:line name length` for every long function (the line of its signature), followed by
`  # long: ...` when it says why and `  MISSING "// long:"` when not; exits 1 when any is missing,
0 otherwise, 2 on bad arguments. Usage:

    scripts/support/long-functions.py [--limit N] [--marker TEXT] [PATH ...]

PATHs are files or folders (default: include src examples under the repository root). Python 3
standard library only, so CI can run it anywhere.

It is a rough finder, not a parser: comments, strings and preprocessor lines are blanked out, then
braces are counted; a brace opens a function body when the code before it, at namespace or class
scope, has a parameter list and is not a class, enum, namespace or variable initialiser. Lambdas
and local classes count as part of the function that holds them.
"""

import argparse
import os
import re
import sys

SOURCE_ENDINGS = (".hpp", ".cpp", ".h", ".cc", ".cxx", ".hxx", ".ipp", ".inl")
DEFAULT_ROOTS = ("include", "src", "examples")


def blank_non_code(text):
    """The text with comments, string and character literals and preprocessor lines replaced by
    spaces (newlines kept, so line numbers stay)."""
    out = []
    i, n = 0, len(text)
    at_line_start = True  # only white space so far on this line
    while i < n:
        c = text[i]
        if c == "\n":
            out.append(c)
            i += 1
            at_line_start = True
            continue
        if at_line_start and c == "#":  # a preprocessor line, with its continuations
            while i < n and text[i] != "\n":
                if text[i] == "\\" and i + 1 < n and text[i + 1] == "\n":
                    out.append(" \n")
                    i += 2
                    continue
                out.append(" ")
                i += 1
            continue
        if not c.isspace():
            at_line_start = False
        if text.startswith("//", i):
            while i < n and text[i] != "\n":
                out.append(" ")
                i += 1
            continue
        if text.startswith("/*", i):
            end = text.find("*/", i + 2)
            end = n if end < 0 else end + 2
            out.append(re.sub(r"[^\n]", " ", text[i:end]))
            i = end
            continue
        raw = re.match(r'(?:u8|u|U|L)?R"([^()\\ ]{0,16})\(', text[i:i + 24])
        if raw and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            close = ")" + raw.group(1) + '"'
            end = text.find(close, i + raw.end())
            end = n if end < 0 else end + len(close)
            out.append(re.sub(r"[^\n]", " ", text[i:end]))
            i = end
            continue
        if c == "'" and i > 0 and text[i - 1].isalnum() and i + 1 < n and text[i + 1].isalnum():
            j = i - 1  # a digit separator (1'000) when the token before it is a number
            while j > 0 and (text[j - 1].isalnum() or text[j - 1] in "._"):
                j -= 1
            if text[j].isdigit():
                out.append(" ")
                i += 1
                continue
        if c in "\"'":
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            end = min(j + 1, n)
            out.append(c + " " * (end - i - 2) + c if end - i >= 2 else " ")
            i = end
            continue
        out.append(c)
        i += 1
    return "".join(out)


def strip_template_prefix(header):
    """`template <...>` prefixes removed (angle brackets balanced)."""
    while True:
        m = re.match(r"\s*template\s*<", header)
        if not m:
            return header
        depth, i = 1, m.end()
        while i < len(header) and depth > 0:
            depth += {"<": 1, ">": -1}.get(header[i], 0)
            i += 1
        header = header[i:]


def top_level_paren(header):
    """Index of the first '(' outside angle brackets, or -1."""
    angle = 0
    for i, c in enumerate(header):
        if c == "<" and not header[max(0, i - 8):i].rstrip().endswith("operator"):
            angle += 1
        elif c == ">" and angle > 0 and header[i - 1] != "-":
            angle -= 1
        elif c == "(" and angle == 0:
            return i
    return -1


NAME = re.compile(r"((?:[\w~]+(?:<[^()]*?>)?::)*(?:operator\s*(?:\(\)|[^\s(]+)|~?\w+))\s*$")


def classify(header):
    """('namespace' | 'class' | 'function' | 'other', name) for the code before a '{'."""
    h = " ".join(header.split())
    h = re.sub(r"^(?:(?:public|private|protected)\s*:\s*)+", "", h)
    h = strip_template_prefix(h).strip()
    if re.match(r"(inline\s+)?namespace\b", h) or re.match(r"extern\s*$", h) or re.match(r'extern\s*"', h):
        return "namespace", ""
    if re.match(r"(?:typedef\s+)?(?:class|struct|union|enum)\b", h):
        return "class", ""
    p = top_level_paren(h)
    if p < 0:
        return "other", ""
    before = h[:p]
    if before.rstrip().endswith("operator"):  # operator()(...)
        q = h.find("(", p + 2)
        before, p = h[:p + 2], q
        if p < 0:
            return "other", ""
    # A variable initialised by a lambda or a call: '=' outside the name's operator.
    if re.search(r"(?<![=!<>])=(?!=)", re.sub(r"operator\s*\S+", "", before)):
        return "other", ""
    m = NAME.search(before)
    if not m:
        return "other", ""
    name = m.group(1)
    if name in ("if", "for", "while", "switch", "catch", "return", "sizeof", "decltype", "alignas"):
        return "other", ""
    return "function", re.sub(r"\s+", "", name) if "operator" not in name else name


def functions(path):
    """Yields (signature line, name, body length in lines, brace line) of each function."""
    with open(path, encoding="utf-8", errors="replace") as f:
        code = blank_non_code(f.read())
    scopes = []  # 'namespace' | 'class' | 'other' | ('function', name, sig_line, brace_line)
    header, header_start = [], None
    paren, line = 0, 1
    i, n = 0, len(code)
    while i < n:
        c = code[i]
        if c == "\n":
            line += 1
        inside_function = any(isinstance(s, tuple) or s == "other" for s in scopes)
        if inside_function:
            if c == "{":
                scopes.append("other")
            elif c == "}":
                top = scopes.pop()
                if isinstance(top, tuple):
                    yield top[2], top[1], line - top[3] + 1, top[3]
                    header, header_start = [], None
            i += 1
            continue
        if c == "(":
            paren += 1
        elif c == ")":
            paren = max(0, paren - 1)
        if c == ":" and paren == 0 and "".join(header).strip() in ("public", "private", "protected"):
            header, header_start = [], None  # an access label: the signature starts after it
            i += 1
            continue
        if paren > 0 or c not in "{};":
            if not c.isspace() and header_start is None:
                header_start = line
            header.append(c)
            i += 1
            continue
        text = "".join(header)
        if c == "{":
            # A constructor's brace-initialised member (": a_{x}, b_{y} {"): part of the header.
            if re.search(r"\)\s*(?:noexcept\s*)?:", text) and re.search(r"[\w>]\s*$", text):
                depth, j = 0, i
                while j < n:
                    depth += {"{": 1, "}": -1}.get(code[j], 0)
                    if code[j] == "\n":
                        line += 1
                    header.append(code[j])
                    j += 1
                    if depth == 0:
                        break
                i = j
                continue
            kind, name = classify(text)
            if kind == "function":
                scopes.append(("function", name, header_start or line, line))
            else:
                scopes.append(kind)
        elif c == "}" and scopes:
            scopes.pop()
        header, header_start = [], None
        i += 1


def reason_above(lines, sig_line, marker):
    """The marker comment in the comment lines directly above line `sig_line` (1-based), or None.
    A `template <...>` line above the signature counts as the signature."""
    k = sig_line - 2
    while k >= 0 and re.match(r"\s*template\s*<", lines[k]):
        k -= 1
    while k >= 0 and lines[k].lstrip().startswith("//"):
        pos = lines[k].find(marker)
        if pos >= 0:
            return lines[k][pos:].strip()
        k -= 1
    return None


def source_files(paths):
    for p in paths:
        if os.path.isfile(p):
            yield p
            continue
        for root, dirs, files in os.walk(p):
            dirs[:] = sorted(d for d in dirs if not d.startswith(".") and d != "build")
            for f in sorted(files):
                if f.endswith(SOURCE_ENDINGS):
                    yield os.path.join(root, f)


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("paths", nargs="*", help="files or folders (default: include src examples)")
    parser.add_argument("--limit", type=int, default=100, help="most lines a function may have without a reason (100)")
    parser.add_argument("--marker", default="// long:", help='the comment that says why ("// long:")')
    args = parser.parse_args(argv)
    if args.limit < 1:
        parser.error("--limit must be at least 1")
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    paths = args.paths or [os.path.join(root, d) for d in DEFAULT_ROOTS if os.path.isdir(os.path.join(root, d))]
    missing = 0
    for path in source_files(paths):
        with open(path, encoding="utf-8", errors="replace") as f:
            lines = f.read().split("\n")
        shown = os.path.relpath(path, root) if not args.paths else path
        for sig_line, name, length, _ in functions(path):
            if length <= args.limit:
                continue
            reason = reason_above(lines, sig_line, args.marker)
            if reason is None:
                missing += 1
                print(f'{shown}:{sig_line} {name} {length}  MISSING "{args.marker}"')
            else:
                print(f"{shown}:{sig_line} {name} {length}  # {reason.lstrip('/ ').strip()}")
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
