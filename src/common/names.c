/*
 * names.c — file names (names.h): the case-insensitive suffix test, and the
 * "human" order of file names for folders of slices:
 * "s2.png" < "s10.png", because microscopes and export scripts rarely pad
 * their slice numbers. Runs of digits compare by numeric value (of any
 * length, without overflow), other characters case-insensitively; ties are
 * broken so that the order is total and deterministic (qsort needs that).
 */
#include "names.h"

#include <string.h>

static int is_digit(char c) { return c >= '0' && c <= '9'; }

static int lower(unsigned char c) { return (c >= 'A' && c <= 'Z') ? c + ('a' - 'A') : c; }

bool bvox__ends_with_ci(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    if (n < m) return false;
    s += n - m;
    for (size_t i = 0; i < m; i++)
        if (lower((unsigned char)s[i]) != lower((unsigned char)suffix[i])) return false;
    return true;
}

int bvox__natural_compare(const char *a, const char *b)
{
    const char *p = a, *q = b;
    int zeros_tiebreak = 0; /* "s01" vs "s1": equal value, fewer zeros first */
    while (*p && *q) {
        if (is_digit(*p) && is_digit(*q)) {
            const char *p0 = p, *q0 = q;
            while (*p == '0') p++;
            while (*q == '0') q++;
            const char *ps = p, *qs = q;
            while (is_digit(*p)) p++;
            while (is_digit(*q)) q++;
            size_t lp = (size_t)(p - ps), lq = (size_t)(q - qs);
            /* Without leading zeros, a longer digit run is a larger number. */
            if (lp != lq) return lp < lq ? -1 : 1;
            int c = memcmp(ps, qs, lp);
            if (c) return c < 0 ? -1 : 1;
            if (!zeros_tiebreak && (ps - p0) != (qs - q0))
                zeros_tiebreak = (ps - p0) < (qs - q0) ? -1 : 1;
            continue;
        }
        int cp = lower((unsigned char)*p), cq = lower((unsigned char)*q);
        if (cp != cq) return cp < cq ? -1 : 1;
        p++;
        q++;
    }
    if (*p || *q) return *p ? 1 : -1; /* a prefix sorts first */
    if (zeros_tiebreak) return zeros_tiebreak;
    int c = strcmp(a, b); /* differ only in letter case */
    return c < 0 ? -1 : (c > 0 ? 1 : 0);
}
