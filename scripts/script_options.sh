# shellcheck shell=bash
# Sourced by the result scripts (scale_sweep.sh, thesis_results.sh): one
# option loop and one python lookup, so that each script only declares its
# options. Usage, after setting the defaults:
#   declare -A value_opts=([--out]=out [--size]=size)         # option -> variable set to the next argument
#   declare -A flag_opts=([--skip-resolution]="skip_res=1")   # option -> assignment made when given
#   positional=suite                                           # variable for a bare argument ('' refuses them)
#   parse_options "$0" LAST_HELP_LINE "$@"
# -h/--help prints the script's header comment (lines 2..LAST_HELP_LINE).
# Errors are one line naming the option, exit status 2.

# prog_name PATH -> "scale_sweep.sh"
prog_name() { basename "$1"; }

parse_options() {
  local script="$1" help_end="$2" prog
  prog="$(prog_name "$1")"
  shift 2
  while (($#)); do
    if [[ "$1" == -h || "$1" == --help ]]; then
      sed -n "2,${help_end}p" "$script"
      exit 0
    elif [[ -n "${value_opts[$1]+set}" ]]; then
      (($# >= 2)) || { echo "$prog: error: $1 needs a value" >&2; exit 2; }
      printf -v "${value_opts[$1]}" '%s' "$2"
      shift 2
    elif [[ -n "${flag_opts[$1]+set}" ]]; then
      eval "${flag_opts[$1]}"
      shift
    elif [[ "$1" != -* && -n "${positional:-}" ]]; then
      printf -v "$positional" '%s' "$1"
      shift
    else
      echo "$prog: error: unknown option '$1' (see --help)" >&2
      exit 2
    fi
  done
}

# Sets `python` to MANYLIGHTS_PYTHON, else the first of the PATH's python3 and
# the system one that imports matplotlib (as `manylights bench --plot` does);
# exits 2 naming the script when there is none.
find_plot_python() {
  local prog
  prog="$(prog_name "$1")"
  python="${MANYLIGHTS_PYTHON:-}"
  if [[ -z "$python" ]]; then
    for p in python3 /usr/bin/python3; do
      if "$p" -c 'import matplotlib' >/dev/null 2>&1; then python="$p"; break; fi
    done
  fi
  if [[ -z "$python" ]]; then
    echo "$prog: error: no python3 with matplotlib; install python3-matplotlib (or set MANYLIGHTS_PYTHON)" >&2
    exit 2
  fi
}
