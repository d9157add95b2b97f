# Sourced by the build scripts: cmake_generator_args DIR prints the -G option for a build directory. Ninja (it keeps
# both cores of a CI machine busy across targets and directories) for a new directory or one already Ninja's; an
# existing directory of another generator keeps it (CMake refuses to change the generator of a directory).
cmake_generator_args() {
  local dir="$1"
  if command -v ninja > /dev/null && { [ ! -f "$dir/CMakeCache.txt" ] || grep -q "^CMAKE_GENERATOR:INTERNAL=Ninja$" "$dir/CMakeCache.txt"; }; then
    echo "-G Ninja"
  fi
}
