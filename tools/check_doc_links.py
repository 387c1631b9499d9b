#!/usr/bin/env python3
"""Checks the relative links of the project's Markdown files: every linked file exists and every #anchor names a
heading of its target (GitHub's slugs). Usage: check_doc_links.py ROOT. Exit 1 listing each broken link."""
import os
import re
import sys

LINK = re.compile(r'\]\(([^)\s]+)\)')
FENCE = re.compile(r'^(```|~~~)')


def slug(heading):
    s = re.sub(r'[^\w\- ]', '', heading.strip().lower())
    return s.replace(' ', '-')


def markdown_lines(path):
    """Yields (line number, line, inside a fenced code block)."""
    fenced = False
    with open(path, encoding='utf-8') as f:
        for number, line in enumerate(f, 1):
            if FENCE.match(line):
                fenced = not fenced
                continue
            yield number, line, fenced


def anchors(path, cache={}):
    if path not in cache:
        seen = {}
        for _, line, fenced in markdown_lines(path):
            m = None if fenced else re.match(r'^#{1,6} (.*)', line)
            if m:
                base = slug(m.group(1))
                n = seen.get(base, 0)
                seen[base] = n + 1
                seen.setdefault(base if n == 0 else f'{base}-{n}', 1)
        cache[path] = set(seen)
    return cache[path]


def check(root, path):
    problems = []
    for number, line, fenced in markdown_lines(path):
        if fenced:
            continue
        for url in LINK.findall(re.sub(r'`[^`]*`', '', line)):
            if re.match(r'^[a-z]+:', url):
                continue
            target, _, frag = url.partition('#')
            full = os.path.normpath(os.path.join(os.path.dirname(path), target)) if target else path
            where = f'{os.path.relpath(path, root)}:{number}'
            if not os.path.exists(full):
                problems.append(f'{where}: {url}: no such file')
            elif frag and full.endswith('.md') and frag not in anchors(full):
                problems.append(f'{where}: {url}: no heading #{frag} in {os.path.relpath(full, root)}')
    return problems


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else '.')
    skip = {'build', 'out', '.git', '.gpu', 'node_modules'}
    problems = []
    for folder, dirs, files in os.walk(root):
        dirs[:] = [d for d in dirs if d not in skip and not d.startswith('build')]
        for name in sorted(files):
            if name.endswith('.md'):
                problems += check(root, os.path.join(folder, name))
    for p in problems:
        print(p)
    print(f'check_doc_links: {len(problems)} broken link(s)' if problems else 'check_doc_links: every link resolves')
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main())
