#!/usr/bin/env python3
"""List the C++ functions longer than a limit (default 80 lines) in the given folders.

    tools/long_functions.py [--max-lines N] [--root DIR] [--allow PATH:NAME ...] [FOLDER ...]

FOLDER defaults to core lab app methods (below --root, default: the repository). A
function's length is the number of lines from the first line of its signature to its
closing brace. Every function defined at namespace or class scope counts (lambdas and local
classes count as part of the function that holds them). Prints one line per long function,
`path:line: name: N lines (limit M)`, longest first, and exits 1 when there is any, 0
otherwise (CTest runs it in the unit label). `--allow PATH:NAME` names a function known to be
long that is not counted (listed as "allowed"); an --allow that no longer matches a long
function is itself an error, so the list cannot go stale.

A brace counter, not a parser: comments, string and character literals and preprocessor
lines are blanked first; a block is a function when its head (the text since the last `;`,
`{` or `}` at the same level) holds a parameter list and is not a namespace, class, enum or
initialiser. Needs only Python 3.
"""
import argparse
import os
import re
import sys

SOURCE_ENDINGS = (".cpp", ".hpp", ".h", ".cc", ".hh", ".cxx")
DEFAULT_FOLDERS = ("core", "lab", "app", "methods")


def blank_comments_and_literals(text):
    """The text with comments, string/char literals and preprocessor lines replaced by
    spaces (newlines kept, so that line numbers stay)."""
    out = []
    i, n = 0, len(text)
    at_line_start = True
    while i < n:
        c = text[i]
        if at_line_start and c == "#":
            # A preprocessor line, with its continuation lines.
            while i < n and text[i] != "\n":
                if text[i] == "\\" and i + 1 < n and text[i + 1] == "\n":
                    out.append("  \n")
                    i += 2
                    continue
                out.append(" ")
                i += 1
            continue
        if c == "/" and text.startswith("//", i):
            while i < n and text[i] != "\n":
                out.append(" ")
                i += 1
            continue
        if c == "/" and text.startswith("/*", i):
            end = text.find("*/", i + 2)
            end = n if end < 0 else end + 2
            out.append(re.sub(r"[^\n]", " ", text[i:end]))
            i = end
            continue
        raw = re.match(r'R"([^(\s]*)\(', text[i:i + 20]) if c == "R" else None
        if raw and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            closing = ")" + raw.group(1) + '"'
            end = text.find(closing, i + raw.end())
            end = n if end < 0 else end + len(closing)
            out.append(re.sub(r"[^\n]", " ", text[i:end]))
            i = end
            continue
        if c in "\"'":
            # A digit separator (1'000'000) is not a character literal.
            if c == "'" and i > 0 and text[i - 1].isalnum() and i + 1 < n and text[i + 1].isalnum():
                out.append(" ")
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            out.append(c + " " * (min(j, n) - i - 1) + (c if j < n else ""))
            i = j + 1
            at_line_start = False
            continue
        out.append(c)
        if c == "\n":
            at_line_start = True
        elif not c.isspace():
            at_line_start = False
        i += 1
    return "".join(out)


SCOPE_HEAD = re.compile(r"\b(namespace|class|struct|union|enum)\b")
EXTERN_HEAD = re.compile(r'\bextern\s*"')


def classify(head):
    """'scope' (namespace, class, extern "C"), 'function' or 'other' for a block head."""
    stripped = " ".join(head.split())
    if not stripped:
        return "other"
    if EXTERN_HEAD.search(stripped):
        return "scope"
    paren = stripped.find("(")
    keyword = SCOPE_HEAD.search(stripped)
    if keyword and (paren < 0 or keyword.start() < paren) and not stripped.rstrip().endswith("="):
        # `struct Foo : Base {` or `namespace a {`; not `struct Foo f() {` (rare).
        if not re.search(r"\)\s*(const|noexcept|override|final|->|\{|$)", stripped) or paren < 0:
            return "scope"
    if stripped.endswith("=") or stripped.endswith("return") or paren < 0:
        return "other"
    if re.match(r"^(if|for|while|switch|catch|do|else)\b", stripped):
        return "other"
    return "function"


def function_name(head):
    """The qualified name before the parameter list of a function head."""
    flat = " ".join(head.split())
    depth = 0
    for k, ch in enumerate(flat):
        if ch == "(" and depth == 0:
            match = re.search(r"([A-Za-z_~][\w:~<>,\s]*?|operator\s*\S+?)\s*$", flat[:k])
            if match:
                name = match.group(1).split()[-1] if match.group(1).split() else match.group(1)
                return name
            return flat[:k].split()[-1] if flat[:k].split() else "?"
        if ch == "<":
            depth += 1
        elif ch == ">" and depth > 0:
            depth -= 1
    return "?"


def long_functions(path, text, max_lines):
    """(path, first line, name, lines) for every function of `text` over max_lines."""
    code = blank_comments_and_literals(text)
    found = []
    # Each stack entry: kind of the open block, its head line, its name.
    stack = []
    head_start = 0  # index where the current head begins
    line = 1
    line_at = [0] * (len(code) + 1)
    for k, ch in enumerate(code):
        line_at[k] = line
        if ch == "\n":
            line += 1
    line_at[len(code)] = line

    def first_code_line(start, end):
        for k in range(start, end):
            if not code[k].isspace():
                return line_at[k]
        return line_at[end]

    in_function_depth = 0  # >0 while inside a function body (or a block nested in one)
    k = 0
    n = len(code)
    while k < n:
        ch = code[k]
        if ch == "{":
            if in_function_depth:
                in_function_depth += 1
                stack.append(("inner", 0, ""))
            else:
                head = code[head_start:k]
                kind = classify(head)
                # A brace initialiser inside a constructor's member-initialiser list:
                # `: a_{x}, b_(y) {` (the head ends in an identifier after `) :`).
                if kind == "function" and re.search(r"\)\s*:[^;{}]*[\w>]\s*$", head) and \
                        not re.search(r"\)\s*(const|noexcept|override|final)?\s*$", head):
                    depth = 1
                    j = k + 1
                    while j < n and depth:
                        depth += {"{": 1, "}": -1}.get(code[j], 0)
                        j += 1
                    k = j
                    continue
                if kind == "function":
                    in_function_depth = 1
                    stack.append(("function", first_code_line(head_start, k), function_name(head)))
                else:
                    stack.append((kind, 0, ""))
                head_start = k + 1
        elif ch == "}":
            kind, start_line, name = stack.pop() if stack else ("other", 0, "")
            if in_function_depth:
                in_function_depth -= 1
            if kind == "function":
                length = line_at[k] - start_line + 1
                if length > max_lines:
                    found.append((path, start_line, name, length))
            if not in_function_depth:
                head_start = k + 1
        elif ch == ";" and not in_function_depth:
            head_start = k + 1
        elif ch == ":" and not in_function_depth:
            # `public:` / `private:` / `protected:` end a head.
            before = code[head_start:k].strip()
            if before in ("public", "private", "protected"):
                head_start = k + 1
        k += 1
    return found


def self_test():
    """The counter on a made-up file: what it must count and what it must not."""
    body = "\n".join("  x += %d;" % k for k in range(5))
    text = (
        "namespace a {\n"                                        # 1
        "struct S : Base {\n"                                    # 2
        "  S(int v) : v_{v}, w_(2) {\n" + body + "\n  }\n"    # 3-9: 7 lines
        "  int v_, w_;\n"
        "};\n"
        "const char* brace = \"{{{\";  // } in a comment\n"
        "void f() {\n"                                           # 7 lines with its lambda
        "  auto g = [&](int k) {\n    return k;\n  };\n"
        "  /* { */ char c = '{';\n"
        "  if (c) { g(1); }\n"
        "}\n"
        "}  // namespace a\n")
    found = {name: length for _, _, name, length in long_functions("t.cpp", text, 5)}
    expected = {"S": 7, "f": 7}
    if found != expected:
        print(f"self-test failed: found {found}, expected {expected}")
        return 1
    print("self-test passed")
    return 0


def source_files(root, folders):
    for folder in folders:
        base = os.path.join(root, folder)
        for dirpath, dirnames, filenames in os.walk(base):
            dirnames[:] = sorted(d for d in dirnames if d not in ("build", ".git", "third_party"))
            for name in sorted(filenames):
                if name.endswith(SOURCE_ENDINGS):
                    yield os.path.join(dirpath, name)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folders", nargs="*", default=list(DEFAULT_FOLDERS))
    parser.add_argument("--max-lines", type=int, default=80)
    parser.add_argument("--root", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    parser.add_argument("--allow", action="append", default=[], metavar="PATH:NAME",
                        help="a known long function left open (path relative to the root, name as printed)")
    parser.add_argument("--self-test", action="store_true", help="check the counter on a made-up file")
    args = parser.parse_args(argv)
    if args.self_test:
        return self_test()
    found = []
    for path in source_files(args.root, args.folders):
        with open(path, encoding="utf-8", errors="replace") as handle:
            text = handle.read()
        found.extend(long_functions(os.path.relpath(path, args.root), text, args.max_lines))
    found.sort(key=lambda row: (-row[3], row[0], row[1]))
    allowed = set(args.allow)
    matched = set()
    failing = []
    for path, start, name, length in found:
        key = f"{path}:{name}"
        if key in allowed:
            matched.add(key)
            print(f"{path}:{start}: {name}: {length} lines (limit {args.max_lines}; allowed, left open)")
        else:
            failing.append(key)
            print(f"{path}:{start}: {name}: {length} lines (limit {args.max_lines})")
    stale = sorted(allowed - matched)
    for key in stale:
        print(f"--allow {key}: no such function over {args.max_lines} lines any more; remove it from the list")
    if failing or stale:
        print(f"{len(failing)} function(s) over {args.max_lines} lines, {len(stale)} stale --allow", file=sys.stderr)
        return 1
    if matched:
        print(f"no other function over {args.max_lines} lines in {', '.join(args.folders)}")
        return 0
    print(f"no function over {args.max_lines} lines in {', '.join(args.folders)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
