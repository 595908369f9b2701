/*
 * contour_sweep.c — does any pair of segments cross? A sweep line from left
 * to right (Shamos and Hoey, 1976): the segments cut by the sweep are kept
 * in their vertical order in a treap; only segments that become neighbours
 * in that order (when one is inserted, or when the one between them leaves)
 * are tested. Until the first crossing is found no two of the segments
 * cross, so their order never changes while both are cut: n log n, where
 * testing every pair whose x ranges overlap (the previous check) was
 * quadratic on paths whose edges span the picture (10^5 points: 25 s).
 *
 * Segments are oriented left to right (lexicographic (x, y)); events are
 * their ends in lexicographic order, deletions before insertions at one
 * point (so a segment that starts where another ends is placed against
 * those that go on through the point); segments of length 0 cross nothing
 * and are left out. A segment s
 * that starts at p goes above an active t when p is left of t's line
 * (orientation > 0), or on it and s's far end is left of it; collinear ones
 * are ordered by index (they overlap, and are then neighbours or separated
 * by another segment that touches both, which the tests still see). The
 * caller's test decides what counts (touching at a point does not).
 */
#include "contour_internal.h"

#include <stdlib.h>
#include <string.h>

typedef struct node {
    struct node *l, *r, *p;
    uint32_t prio;
    size_t seg;
} node;

typedef struct sweep {
    const bvox_point2 *a, *b; /* per segment, a <= b lexicographically */
    node *nodes;
    node *root;
} sweep;

static double orient(bvox_point2 a, bvox_point2 b, bvox_point2 c)
{
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

/* 1 if segment s (starting now) goes above active segment t, else 0. */
static int above(const sweep *w, size_t s, size_t t)
{
    double o = orient(w->a[t], w->b[t], w->a[s]);
    if (o == 0) o = orient(w->a[t], w->b[t], w->b[s]);
    if (o == 0) return s > t;
    return o > 0;
}

static int lex_less(bvox_point2 p, bvox_point2 q)
{
    return p.x < q.x || (p.x == q.x && p.y < q.y);
}

/* Segments i and j lie on one line and share more than a point. */
static int overlap(const sweep *w, size_t i, size_t j)
{
    return orient(w->a[i], w->b[i], w->a[j]) == 0 && orient(w->a[i], w->b[i], w->b[j]) == 0 &&
           lex_less(w->a[j], w->b[i]) && lex_less(w->a[i], w->b[j]);
}

static void rotate_up(sweep *w, node *x)
{
    node *p = x->p, *g = p->p;
    if (p->l == x) {
        p->l = x->r;
        if (x->r) x->r->p = p;
        x->r = p;
    } else {
        p->r = x->l;
        if (x->l) x->l->p = p;
        x->l = p;
    }
    p->p = x;
    x->p = g;
    if (!g) w->root = x;
    else if (g->l == p) g->l = x;
    else g->r = x;
}

static void insert(sweep *w, node *x)
{
    x->l = x->r = x->p = NULL;
    if (!w->root) {
        w->root = x;
        return;
    }
    node *cur = w->root;
    for (;;) {
        node **next = above(w, x->seg, cur->seg) ? &cur->r : &cur->l;
        if (!*next) {
            *next = x;
            x->p = cur;
            break;
        }
        cur = *next;
    }
    while (x->p && x->p->prio < x->prio) rotate_up(w, x);
}

static void erase(sweep *w, node *x)
{
    while (x->l || x->r) { /* rotate the higher-priority child up over x */
        node *c = !x->l ? x->r : !x->r ? x->l : x->l->prio > x->r->prio ? x->l : x->r;
        rotate_up(w, c);
    }
    if (!x->p) w->root = NULL;
    else if (x->p->l == x) x->p->l = NULL;
    else x->p->r = NULL;
    x->p = NULL;
}

static node *next_node(node *x)
{
    if (x->r) {
        x = x->r;
        while (x->l) x = x->l;
        return x;
    }
    while (x->p && x->p->r == x) x = x->p;
    return x->p;
}

static node *prev_node(node *x)
{
    if (x->l) {
        x = x->l;
        while (x->r) x = x->r;
        return x;
    }
    while (x->p && x->p->l == x) x = x->p;
    return x->p;
}

typedef struct event {
    bvox_point2 at;
    size_t seg;
    int leave; /* 0: insert, 1: delete */
} event;

static int cmp_event(const void *pa, const void *pb)
{
    const event *e = pa, *f = pb;
    if (e->at.x != f->at.x) return e->at.x < f->at.x ? -1 : 1;
    if (e->at.y != f->at.y) return e->at.y < f->at.y ? -1 : 1;
    if (e->leave != f->leave) return f->leave - e->leave; /* deletions first */
    return (e->seg > f->seg) - (e->seg < f->seg);
}

int bvox__sweep_crossing(const bvox_point2 *p, const bvox_point2 *q, size_t n,
                         int (*test)(void *ctx, size_t i, size_t j), void *ctx)
{
    if (n < 2) return 0;
    bvox_point2 *a = bvox__mem_alloc(n * sizeof *a), *b = bvox__mem_alloc(n * sizeof *b);
    node *nodes = bvox__mem_zalloc(n, sizeof *nodes);
    event *ev = bvox__mem_alloc(2 * n * sizeof *ev);
    int found = -1;
    if (!a || !b || !nodes || !ev) goto done;
    uint32_t rng = 0x9E3779B9u;
    size_t nev = 0;
    for (size_t i = 0; i < n; i++) {
        int swap = lex_less(q[i], p[i]);
        a[i] = swap ? q[i] : p[i];
        b[i] = swap ? p[i] : q[i];
        rng ^= rng << 13, rng ^= rng >> 17, rng ^= rng << 5; /* xorshift priorities */
        nodes[i].prio = rng;
        nodes[i].seg = i;
        if (a[i].x == b[i].x && a[i].y == b[i].y) continue; /* a point crosses nothing */
        ev[nev++] = (event){a[i], i, 0};
        ev[nev++] = (event){b[i], i, 1};
    }
    qsort(ev, nev, sizeof *ev, cmp_event);
    sweep w = {a, b, nodes, NULL};
    found = 0;
    for (size_t k = 0; k < nev && !found; k++) {
        node *x = &nodes[ev[k].seg];
        if (!ev[k].leave) {
            insert(&w, x);
            /* the neighbours; past those lying on x (a run of collinear
             * segments, which only a polygon's own neighbours may form
             * without crossing) the ones beyond too */
            for (node *u = prev_node(x); u && !found; u = prev_node(u)) {
                found = test(ctx, u->seg, x->seg);
                if (!overlap(&w, u->seg, x->seg)) break;
            }
            for (node *v = next_node(x); v && !found; v = next_node(v)) {
                found = test(ctx, x->seg, v->seg);
                if (!overlap(&w, x->seg, v->seg)) break;
            }
        } else {
            node *u = prev_node(x), *v = next_node(x);
            erase(&w, x);
            if (u && v && test(ctx, u->seg, v->seg)) found = 1;
        }
    }
done:
    free(a);
    free(b);
    free(nodes);
    free(ev);
    return found;
}
