# Shared by the consumer projects: consumer_strict(<target>) compiles <target> with the
# flags an exacting embedder uses. -O1 keeps the one translation unit, which instantiates
# every query, quick to build; the warnings below are the front end's, at any level.
# CONSUMER_NO_EXCEPTIONS=ON adds -fno-exceptions.
function(consumer_strict target)
  target_compile_options(${target} PRIVATE
    -O1 -Wall -Wextra -Wpedantic -Wconversion -Wsign-conversion -Wshadow -Werror)
  if(CONSUMER_NO_EXCEPTIONS)
    target_compile_options(${target} PRIVATE -fno-exceptions)
  endif()
endfunction()
