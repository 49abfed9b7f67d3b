#!/usr/bin/env python3
"""Lists the functions and source files that are too long to read in one sitting.

    scripts/code_size.py [--max-function N] [--max-file N] [--all] [--tree] [DIR ...]

Default DIRs: the library folders (mesher2d geom param surface io). A function's length runs
from the first line of its signature to its closing brace; a lambda or local class counts
as part of the function it is in. Exits 1 when a function is longer than --max-function
(120) or a file longer than --max-file (1000) lines, so CI can run it; --all lists every
function with its length, --tree prints every file with its line count.

The parser strips comments and literals, then follows braces: a `{` at namespace or class
scope opens a function body when the text before it (since the previous `;`, `{` or `}`)
has a parameter list and is not a class, enum, namespace or initializer.
"""
import argparse
import os
import re
import sys

SOURCE_EXT = (".cpp", ".cc", ".h", ".hpp", ".inl")
LIBRARY_DIRS = ["mesher2d", "geom", "param", "surface", "io"]


def strip_code(text):
    """Comments, string and character literals become spaces; newlines are kept."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        nxt = text[i + 1] if i + 1 < n else ""
        if c == "/" and nxt == "/":
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif c == "/" and nxt == "*":
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == "R" and nxt == '"' and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            if m:
                end = text.find(")" + m.group(1) + '"', i)
                end = n if end < 0 else end + len(m.group(1)) + 2
                out.append(re.sub(r"[^\n]", " ", text[i:end]))
                i = end
            else:
                out.append(c)
                i += 1
        elif c in "\"'":
            if c == "'" and i > 0 and text[i - 1].isalnum() and nxt.isalnum():
                out.append(" ")  # digit separator, 1'000'000
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            j = min(j + 1, n)
            out.append(c + " " * (j - i - 2) + (c if j - i >= 2 else ""))
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


def _drop_template_prefix(header):
    h = header.strip()
    while h.startswith("template"):
        k = h.find("<")
        depth, j = 0, k
        while j < len(h):
            if h[j] == "<":
                depth += 1
            elif h[j] == ">":
                depth -= 1
                if depth == 0:
                    break
            j += 1
        h = h[j + 1 :].strip()
    return h


def classify(header):
    """What a `{` at namespace or class scope opens, from the text before it."""
    h = _drop_template_prefix(" ".join(header.split()))
    if re.match(r"^(inline\s+)?namespace\b", h) or re.match(r'^extern\s+" "', h) or h.startswith('extern "'):
        return "scope"
    if re.match(r"^((typedef|static|constexpr|inline|const)\s+)*(class|struct|union|enum)\b", h):
        if "(" in h.split("{")[0] and re.search(r"\)\s*(const|noexcept|override|final|->[^=]*)*\s*$", h):
            return "function"  # struct Foo f(...) { (a function returning a struct)
        return "scope"
    if h.startswith("#"):
        return "scope"
    depth = 0
    for ch in h:
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
        elif ch == "=" and depth == 0:
            return "data"
    if "(" in h:
        return "function"
    return "data"


def functions_of(path):
    with open(path, encoding="utf-8", errors="replace") as f:
        text = f.read()
    code = strip_code(text)
    # Preprocessor lines carry no braces we can follow reliably.
    code = re.sub(r"(?m)^[ \t]*#.*(\\\n.*)*$", lambda m: re.sub(r"[^\n]", " ", m.group(0)), code)
    found = []
    stack = []  # entries: (kind, start_line, name)
    header_start = 0
    line = 1
    header_first_line = None
    for i, ch in enumerate(code):
        if ch == "\n":
            line += 1
            continue
        in_function = any(k == "function" for k, _, _ in stack)
        if in_function:
            if ch == "{":
                stack.append(("block", line, ""))
            elif ch == "}":
                kind, start, name = stack.pop()
                if kind == "function":
                    found.append((name, start, line))
                    header_start = i + 1
                    header_first_line = None
            continue
        if not ch.isspace() and header_first_line is None and ch not in ";{}":
            header_first_line = line
        if ch == ";":
            header_start = i + 1
            header_first_line = None
        elif ch == "{":
            header = code[header_start:i]
            kind = classify(header)
            if kind == "function" and re.search(r"\)\s*:", header) and re.search(r"[\w>]\s*$", header) \
                    and not re.search(r"\b(const|override|final|noexcept|mutable)\s*$", header):
                stack.append(("init", line, ""))  # a member's brace initializer: Foo() : a_{1} {
                continue
            name = ""
            if kind == "function":
                m = re.search(r"([~\w:<>]+(?:operator\s*[^\s(]+)?)\s*\(", " ".join(header.split()))
                name = m.group(1) if m else "?"
            stack.append((kind, header_first_line or line, name))
            header_start = i + 1
            header_first_line = None
        elif ch == "}":
            if stack:
                kind, _, _ = stack.pop()
                if kind == "init":
                    continue
            header_start = i + 1
            header_first_line = None
    return found, text.count("\n") + (0 if text.endswith("\n") else 1)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dirs", nargs="*")
    ap.add_argument("--max-function", type=int, default=120)
    ap.add_argument("--max-file", type=int, default=1000)
    ap.add_argument("--all", action="store_true", help="list every function with its length")
    ap.add_argument("--tree", action="store_true", help="list every file with its line count")
    args = ap.parse_args()
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    dirs = args.dirs or [os.path.join(root, d) for d in LIBRARY_DIRS]
    long_functions, long_files, files = [], [], []
    for d in dirs:
        for base, subdirs, names in os.walk(d):
            subdirs.sort()
            for nm in sorted(names):
                if not nm.endswith(SOURCE_EXT):
                    continue
                p = os.path.join(base, nm)
                rel = os.path.relpath(p, root)
                funcs, nlines = functions_of(p)
                files.append((rel, nlines))
                if nlines > args.max_file:
                    long_files.append((rel, nlines))
                for name, a, b in funcs:
                    length = b - a + 1
                    if args.all:
                        print(f"{length:5d}  {rel}:{a}  {name}")
                    if length > args.max_function:
                        long_functions.append((length, rel, a, name))
    if args.tree:
        for rel, nlines in files:
            print(f"{nlines:6d}  {rel}")
        print(f"{sum(n for _, n in files):6d}  total, {len(files)} files")
    for length, rel, a, name in sorted(long_functions, reverse=True):
        print(f"function over {args.max_function} lines: {rel}:{a} {name} ({length} lines)")
    for rel, nlines in sorted(long_files, key=lambda x: -x[1]):
        print(f"file over {args.max_file} lines: {rel} ({nlines} lines)")
    if long_functions or long_files:
        print(f"code_size: {len(long_functions)} functions and {len(long_files)} files too long", file=sys.stderr)
        return 1
    print(f"code_size: every function <= {args.max_function} lines, every file <= {args.max_file} lines")
    return 0


if __name__ == "__main__":
    sys.exit(main())
