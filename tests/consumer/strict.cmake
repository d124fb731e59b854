# Shared by the consumer projects: consumer_strict(<target>) compiles <target> with the
# flags an exacting embedder uses. -O0 keeps the one translation unit, which instantiates
# every query, quick to build (the project's own suites build the kernel at -O2); the
# warnings below come from the front end, at any level.
# CONSUMER_NO_EXCEPTIONS=ON adds -fno-exceptions.
function(consumer_strict target)
  target_compile_options(${target} PRIVATE
    -O0 -Wall -Wextra -Wpedantic -Wconversion -Wsign-conversion -Wshadow -Werror)
  if(CONSUMER_NO_EXCEPTIONS)
    target_compile_options(${target} PRIVATE -fno-exceptions)
  endif()
endfunction()
