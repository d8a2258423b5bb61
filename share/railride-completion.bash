# bash completion for railride: commands, then the options the command's own
# --help lists (so it never goes stale), then files for VEHICLE, PROBLEM,
# --plot and the options that take a file.
_railride()
{
  local cur prev cmd
  cur=${COMP_WORDS[COMP_CWORD]}
  prev=${COMP_WORDS[COMP_CWORD-1]}
  if [ "$COMP_CWORD" -eq 1 ]; then
    local cmds
    cmds=$("${COMP_WORDS[0]}" --help 2>/dev/null | awk '/^  [a-z]/ {print $1}')
    COMPREPLY=($(compgen -W "$cmds --help --version" -- "$cur"))
    return
  fi
  cmd=${COMP_WORDS[1]}
  case $prev in
    --plot|--plot-script|--psd|--track|--output|--profile|--spectrum) COMPREPLY=($(compgen -f -- "$cur")); return ;;
  esac
  if [[ $cur == -* ]]; then
    local opts
    opts=$("${COMP_WORDS[0]}" "$cmd" --help 2>/dev/null | grep -o -- '--[a-z][a-z-]*' | sort -u)
    COMPREPLY=($(compgen -W "$opts --plot" -- "$cur"))
  else
    COMPREPLY=($(compgen -f -- "$cur") $(compgen -W "type1 type2" -- "$cur"))
  fi
}
complete -F _railride railride
