#!/bin/sh
# options.sh — every command is described once, as data: its --help lists
# exactly the options its parser accepts (each listed option is taken, with
# its short alias; an option listed by another command but not by this one,
# or one nobody lists, is refused with exit 2), and the generated manual
# page and bash completion name the same options. The manual pages render
# without warnings (groff -ww) where groff is installed.
# Usage: sh options.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }

cmds=$("$BVOX" --help | sed -n '/^Commands:/,/^$/s/^  \([a-z][a-z-]*\) .*/\1/p')
[ "$(echo "$cmds" | wc -l)" -ge 19 ] || fail "--help lists too few commands: $cmds"

# The option lines of a --help text: "NAME VALUE?" per option, VALUE 1 when
# the option takes a value; short aliases as their own line.
options_of() {
    grep -- '^  -' "$1" | sed 's/^  //; s/  .*//' | awk '{
        if ($1 ~ /^-.,$/) { short = substr($1, 1, 2); long = $2; v = (NF > 2) }
        else { short = ""; long = $1; v = (NF > 1) }
        print long, v
        if (short != "") print short, v
    }'
}

: >"$tmp/all"
for c in $cmds; do
    "$BVOX" "$c" --help >"$tmp/help.$c" || fail "$c --help exited $?"
    options_of "$tmp/help.$c" >"$tmp/opts.$c"
    grep -q '^--help 0$' "$tmp/opts.$c" || fail "$c --help does not list --help"
    grep -q '^-h 0$' "$tmp/opts.$c" || fail "$c --help does not list -h"
    [ "$(wc -l <"$tmp/opts.$c")" -ge 4 ] || fail "$c lists too few options"
    # an option listed twice would be a table that two groups both own
    dup=$(cut -d' ' -f1 "$tmp/opts.$c" | sort | uniq -d)
    [ -z "$dup" ] || fail "$c --help lists $dup twice"
    cut -d' ' -f1 "$tmp/opts.$c" >>"$tmp/all"
done
# The global options (main.c takes --quiet out of any command line) are
# every command's: not among those a command must refuse.
"$BVOX" --help >"$tmp/help.bvox"
sed -n '/^Global options:/,/^$/p' "$tmp/help.bvox" >"$tmp/global.txt"
options_of "$tmp/global.txt" | cut -d' ' -f1 | sort -u >"$tmp/global"
grep -qx -- --quiet "$tmp/global" || fail "bvox --help does not list the global --quiet"
sort -u "$tmp/all" | comm -23 - "$tmp/global" >"$tmp/all.cmd"
mv "$tmp/all.cmd" "$tmp/all"

# run CMD ARGS...: exit status in $rc, stderr in $tmp/err, stdout in $tmp/out
run() {
    set +e
    "$BVOX" "$@" >"$tmp/out" 2>"$tmp/err"
    rc=$?
    set -e
}

for c in $cmds; do
    # Each listed option is taken: with a value (valid or not) before an
    # unknown option, the parser gets past it and stops at the unknown one,
    # or complains about the value, naming the option; never "unknown".
    while read -r name takes; do
        case $name in --help|-h) continue ;; esac
        if [ "$takes" = 1 ]; then run "$c" "$name" 1 --zz-not-an-option
        else run "$c" "$name" --zz-not-an-option; fi
        [ "$rc" -eq 2 ] || fail "$c $name: exit $rc, expected 2 ($(cat "$tmp/err"))"
        [ ! -s "$tmp/out" ] || fail "$c $name wrote to stdout"
        [ "$(wc -l <"$tmp/err")" -eq 1 ] || fail "$c $name: stderr is not one line"
        if grep -q "unknown option '--zz-not-an-option'" "$tmp/err"; then :
        elif grep -q "unknown option" "$tmp/err"; then
            fail "$c does not accept its listed $name: $(cat "$tmp/err")"
        else
            # a complaint about the value (or another rule): it must name the option
            long=$(grep -- "^$name " "$tmp/opts.$c" >/dev/null && echo "$name")
            grep -q -- "${long#-?}" "$tmp/err" ||
                fail "$c $name 1: neither taken nor refused by name: $(cat "$tmp/err")"
        fi
    done <"$tmp/opts.$c"
done
# Everything else is refused: nonsense by every command, and each option of
# one command by the commands that do not list it (a fifth of those pairs,
# rotating, so that every option and every command takes part).
ci=0
for c in $cmds; do
    ci=$((ci + 1))
    cut -d' ' -f1 "$tmp/opts.$c" | sort >"$tmp/mine"
    k=0
    for name in $(comm -23 "$tmp/all" "$tmp/mine") --zz-not-an-option; do
        k=$((k + 1))
        [ "$name" = --zz-not-an-option ] || [ $(((k + ci) % 5)) -eq 0 ] || continue
        run "$c" "$name"
        [ "$rc" -eq 2 ] || fail "$c accepts $name, which its --help does not list (exit $rc)"
        grep -q "^bvox: $c: unknown option '$name'" "$tmp/err" ||
            fail "$c $name: $(cat "$tmp/err")"
    done
done

# The parser's forms: --name=VALUE and -o=VALUE, a missing value, "--"
# ending the options, a flag that is given a value.
run info a.nii --threshold=abc
[ "$rc" -eq 2 ] && grep -q "^bvox: info: --threshold: 'abc' is not a finite number" "$tmp/err" ||
    fail "--threshold=abc: $(cat "$tmp/err")"
run info a.nii --threshold
[ "$rc" -eq 2 ] && grep -q "^bvox: info: option --threshold needs a value" "$tmp/err" ||
    fail "--threshold without a value: $(cat "$tmp/err")"
run mesh a.nii -o=b.xyz
[ "$rc" -eq 2 ] && grep -q "b.xyz: the extension must be" "$tmp/err" || fail "-o=b.xyz: $(cat "$tmp/err")"
run info -- --json
[ "$rc" -eq 1 ] && grep -q -- "--json" "$tmp/err" || fail "info -- --json: $(cat "$tmp/err")"
run info a.nii --json=1
[ "$rc" -eq 2 ] && grep -q "unknown option '--json=1'" "$tmp/err" || fail "--json=1: $(cat "$tmp/err")"

# Manual pages: bvox(1) names every command; bvox-CMD(1) every option of
# CMD's --help (long names; -h and the aliases are in the same lines).
"$BVOX" help --man >"$tmp/bvox.1" || fail "help --man exited $?"
head -3 "$tmp/bvox.1" | grep -q '^\.TH BVOX 1 ' || fail "bvox.1 has no .TH line"
for c in $cmds; do
    grep -q "^\.B $c\$" "$tmp/bvox.1" || fail "bvox(1) does not list $c"
    grep -q "^\.BR bvox\\\\-$c (1)" "$tmp/bvox.1" || fail "bvox(1) does not refer to bvox-$c(1)"
    "$BVOX" help --man "$c" >"$tmp/$c.1" || fail "help --man $c exited $?"
    grep -q "^\.TH BVOX-$(echo "$c" | tr a-z A-Z) 1 " "$tmp/$c.1" || fail "$c.1 .TH"
    for name in $(grep -- '^--' "$tmp/opts.$c" | cut -d' ' -f1); do
        roff=$(echo "$name" | sed 's/-/\\\\-/g')
        grep -q "^\\\\fB$roff\\\\fR\|, \\\\fB$roff\\\\fR" "$tmp/$c.1" ||
            fail "bvox-$c(1) does not document $name"
    done
done
if command -v groff >/dev/null 2>&1; then
    for page in "$tmp"/*.1; do
        groff -man -Tascii -ww -z "$page" 2>"$tmp/warn" || fail "groff failed on $page"
        [ ! -s "$tmp/warn" ] || fail "groff warns on $(basename "$page"): $(head -3 "$tmp/warn")"
    done
    # rendered, the options read as typed
    groff -man -Tascii -P-cbou "$tmp/morph.1" 2>/dev/null | grep -q -- '--min-size N' ||
        fail "morph.1 does not render --min-size N"
else
    echo "groff not installed: manual pages not rendered"
fi
run help --man frobnicate
[ "$rc" -eq 2 ] || fail "help --man frobnicate exited $rc"
run help --man info extra
[ "$rc" -eq 2 ] || fail "help --man info extra exited $rc"
run help --bash-completion extra
[ "$rc" -eq 2 ] || fail "help --bash-completion extra exited $rc"

# Bash completion: valid bash; "--" after a command offers exactly the
# options of its --help; a choice option offers its words.
"$BVOX" help --bash-completion >"$tmp/bvox.bash" || fail "help --bash-completion exited $?"
if command -v bash >/dev/null 2>&1; then
    bash -n "$tmp/bvox.bash" || fail "the completion script is not valid bash"
    complete_words() { # complete_words WORD...: completions of the last word
        bash -c '. "$1"; shift; COMP_WORDS=("$@"); COMP_CWORD=$(($# - 1)); _bvox
                 printf "%s\n" "${COMPREPLY[@]}"' sh "$tmp/bvox.bash" bvox "$@"
    }
    complete_words "" | sort >"$tmp/c.top"
    for c in $cmds help --help --version; do
        grep -qx -- "$c" "$tmp/c.top" || fail "completion of the first word lacks $c"
    done
    for c in $cmds; do
        complete_words "$c" x - | sort >"$tmp/c.$c"
        cut -d' ' -f1 "$tmp/opts.$c" | sort >"$tmp/h.$c"
        cmp -s "$tmp/c.$c" "$tmp/h.$c" ||
            fail "completion of '$c -' differs from its --help: $(diff "$tmp/h.$c" "$tmp/c.$c" | head -5)"
    done
    [ "$(complete_words morph x --conn "" | tr '\n' ' ')" = "6 18 26 " ] ||
        fail "completion of morph --conn: $(complete_words morph x --conn "")"
    [ "$(complete_words cut x --keep b)" = below ] || fail "completion of cut --keep b"
    [ "$(complete_words info x --threshold "" | wc -w)" -eq 0 ] ||
        fail "completion after --threshold offers words"
else
    echo "bash not installed: completion not exercised"
fi
echo "ok"
