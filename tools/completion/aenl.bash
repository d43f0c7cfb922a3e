# SPDX-License-Identifier: MIT
# bash completion for aenl: subcommands, then the options that `aenl SUBCOMMAND --help` lists
# (read from the installed binary, so the list is always the binary's own), then file names.
_aenl() {
  local cur=${COMP_WORDS[COMP_CWORD]}
  if [[ $COMP_CWORD -eq 1 ]]; then
    local subs
    subs=$(aenl --help 2>/dev/null | awk '/^  [a-z]/ {print $1}')
    mapfile -t COMPREPLY < <(compgen -W "$subs --help --version" -- "$cur")
    return
  fi
  if [[ $cur == -* ]]; then
    local opts sub=("${COMP_WORDS[1]}")
    # bench's kinds have their own options (aenl bench null --help)
    [[ ${COMP_WORDS[1]} == bench && $COMP_CWORD -gt 2 && ${COMP_WORDS[2]} != -* ]] &&
      sub+=("${COMP_WORDS[2]}")
    opts=$(aenl "${sub[@]}" --help 2>/dev/null | grep -o -- '--[a-z][a-z0-9-]*' | sort -u)
    mapfile -t COMPREPLY < <(compgen -W "$opts --help" -- "$cur")
    return
  fi
  mapfile -t COMPREPLY < <(compgen -f -- "$cur")
}
complete -o filenames -F _aenl aenl
