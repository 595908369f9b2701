#!/usr/bin/env python3
"""check-includes.py — no circles between the library's files.

A circle is two (or more) files of src/ that each use something the other
defines: a.c calls a function of b.c (through b's header) and b.c calls one
of a.c. Such a pair is one concern split in two, or a container that also
dispatches; issue 12 opened them by moving code, and this check keeps them
open. It reads the sources only (no build): a file's definitions are its
non-static functions and global tables (bvox_* / bvox__* names at the start
of a line, followed by a body); a file uses every such name it mentions.
Circles are the strongly connected components of "uses" with more than one
file. Headers are checked too: no header may include itself through others
(#include "..." resolved beside the file, then from src/). With --rooms, the
same question between rooms (src/<room>/) is printed, for information.

Usage: check-includes.py [--rooms] [SRC_DIR]   (default: src/ beside scripts/)
Exit 0: no circle; 1: circles, one a line.
"""
import os
import re
import sys

DEF_FUNC = re.compile(
    r'^(?!static\b|extern\b|typedef\b|#)[A-Za-z_][^;{}()=#]*?\b(bvox_\w+)\s*'
    r'\((?:[^()]|\([^()]*\))*\)\s*\{', re.M)
DEF_DATA = re.compile(
    r'^(?!static\b|extern\b|typedef\b|#)[A-Za-z_][^;{}()=#]*?\b(bvox_\w+)\s*(?:\[[^\]]*\]\s*)*=',
    re.M)
NAME = re.compile(r'\bbvox_\w+\b')
COMMENT = re.compile(r'/\*.*?\*/|//[^\n]*', re.S)
STRING = re.compile(r'"(?:\\.|[^"\\\n])*"')


INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def sources(src, ext='.c'):
    for root, _, files in os.walk(src):
        for f in sorted(files):
            if f.endswith(ext):
                yield os.path.relpath(os.path.join(root, f), src)


def header_edges(src):
    """Header -> the library headers it includes."""
    edges = {}
    for h in sources(src, '.h'):
        with open(os.path.join(src, h), encoding='utf-8', errors='replace') as f:
            text = COMMENT.sub(' ', f.read())
        for inc in INCLUDE.findall(text):
            for cand in (os.path.join(os.path.dirname(h), inc), inc):
                cand = os.path.normpath(cand)
                if os.path.isfile(os.path.join(src, cand)):
                    edges.setdefault(h, set()).add(cand)
                    break
    return edges


def strip(text):
    return STRING.sub('""', COMMENT.sub(' ', text))


def sccs(nodes, edges):
    """Tarjan's strongly connected components, iteratively."""
    index, low, on, stack, out, counter = {}, {}, set(), [], [], [0]
    for root in nodes:
        if root in index:
            continue
        work = [(root, iter(sorted(edges.get(root, ()))))]
        index[root] = low[root] = counter[0]
        counter[0] += 1
        stack.append(root)
        on.add(root)
        while work:
            v, it = work[-1]
            for w in it:
                if w not in index:
                    index[w] = low[w] = counter[0]
                    counter[0] += 1
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(edges.get(w, ())))))
                    break
                if w in on:
                    low[v] = min(low[v], index[w])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[v])
                if low[v] == index[v]:
                    comp = []
                    while True:
                        w = stack.pop()
                        on.discard(w)
                        comp.append(w)
                        if w == v:
                            break
                    if len(comp) > 1:
                        out.append(sorted(comp))
    return out


def main(argv):
    rooms = '--rooms' in argv
    args = [a for a in argv if not a.startswith('--')]
    src = args[0] if args else os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'src')
    text = {f: strip(open(os.path.join(src, f), encoding='utf-8', errors='replace').read())
            for f in sources(src)}
    owner = {}
    for f, t in text.items():
        for rx in (DEF_FUNC, DEF_DATA):
            for m in rx.finditer(t):
                owner.setdefault(m.group(1), f)
    uses = {f: set() for f in text}
    why = {}
    for f, t in text.items():
        for name in set(NAME.findall(t)):
            g = owner.get(name)
            if g and g != f:
                uses[f].add(g)
                why.setdefault((f, g), name)
    bad = 0
    for comp in sccs(sorted(text), uses):
        pairs = ', '.join('%s uses %s (%s)' % (a, b, why[(a, b)])
                          for a in comp for b in comp if (a, b) in why)
        print('circle: %s: %s' % (' <-> '.join(comp), pairs))
        bad += 1
    hedges = header_edges(src)
    for comp in sccs(sorted(hedges), hedges):
        print('header circle: %s' % ' <-> '.join(comp))
        bad += 1
    if rooms:
        room = lambda f: f.split('/')[0] if '/' in f else '.'
        redges = {}
        for f, gs in uses.items():
            for g in gs:
                if room(f) != room(g):
                    redges.setdefault(room(f), set()).add(room(g))
                    why.setdefault((room(f), room(g)), '%s -> %s' % (f, g))
        for comp in sccs(sorted(redges), redges):
            print('room circle: %s: %s' % (' <-> '.join(comp), ', '.join(
                '%s (%s)' % (a + ' uses ' + b, why[(a, b)]) for a in comp for b in comp
                if (a, b) in why)))
    if bad:
        print('%d circle(s) between files of %s' % (bad, src))
        return 1
    print('no circles between the %d files of %s' % (len(text), src))
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
