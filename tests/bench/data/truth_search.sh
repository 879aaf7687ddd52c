#!/bin/sh
# A program that hunts for the truth, as a dishonest estimator would (issue 39): it
# looks for the paths it is given (the run's --out, another run's truth, the user's
# home, the scene file), the harness in /proc, other cases' and programs' folders in
# the temporary folder, and files named like the harness's cases and truth anywhere it
# can look. What it finds goes into the answer's notes ("found: none" when nothing).
#   truth_search.sh [--find] [--persistent] [--own=PATH]... [@PATH]... [request.json]
# @PATH: a place to look (not a path, so the harness does not show it as a file the
# command names); a folder counts when a file under it is readable.
# --own=PATH: what it was given (its `readable`, the harness's files): not a find.
# --find: also search the whole file system it sees (slow outside a sandbox).
# --persistent: answer JSON lines on stdin (grapebench-estimator-2, persistent mode);
# otherwise write answer.json in the working folder.

# Its own: its script, the working folder, what it was given and (persistent mode) the
# folder its requests are in. Prints the paths, one a line, for grep -F -v.
own_list() {
  printf '%s\n' "$0" "$PWD"
  [ -n "$inbox" ] && printf '%s\n' "$inbox"
  for o in $owns; do printf '%s\n' "$o"; done
}

not_own() {
  grep -v -F -f "$ownfile"
}

search() {
  ownfile="$PWD/.own"
  own_list > "$ownfile"
  found=""
  for p in $paths; do
    if [ -d "$p" ]; then
      f=$(find "$p" -type f 2>/dev/null | not_own | head -1)
      [ -n "$f" ] && found="$found $p"
    elif [ -e "$p" ]; then
      [ -n "$(printf '%s\n' "$p" | not_own)" ] && found="$found $p"
    fi
  done
  for c in /proc/[0-9]*/cmdline; do
    if tr '\0' ' ' < "$c" 2>/dev/null | grep -q 'grapebench run'; then found="$found $c"; fi
  done
  # Other programs' and cases' folders (the harness's temporary folders).
  for d in /tmp/grapebench-* /var/tmp/grapebench-*; do
    [ -e "$d" ] || continue
    [ -n "$(printf '%s\n' "$d" | not_own)" ] && found="$found $d"
  done
  if [ "$find" = 1 ]; then
    # The system's folders excepted: they hold no run's files.
    for f in $(find / \( -path /proc -o -path /sys -o -path /dev -o -path /usr \) -prune -o \
                 \( -name 'ground_truth.json' -o -name 'c[0-9]*_b[0-9]*.json' -o -name 'results.csv' \
                    -o -name 'summary.json' -o -name 'manifest.json' \) -print 2>/dev/null | not_own | head -20); do
      found="$found $f"
    done
  fi
  rm -f "$ownfile"
  [ -n "$found" ] || found=" none"
  echo "found:$found" | cut -c1-390
}

find=0
persistent=0
paths=""
owns=""
for a in "$@"; do
  case "$a" in
    --find) find=1 ;;
    --persistent) persistent=1 ;;
    --own=*) owns="$owns ${a#--own=}" ;;
    @*) paths="$paths ${a#@}" ;;
  esac
done

inbox=""
if [ "$persistent" = 1 ]; then
  while read -r line; do
    inbox=$(printf '%s' "$line" | sed -n 's|.*"\(/[^"]*\)/request/[^"]*".*|\1|p')
    printf '{"volume": 0.001, "notes": "%s"}\n' "$(search)"
  done
else
  printf '{"volume": 0.001, "notes": "%s"}\n' "$(search)" > answer.json
fi
