# fp_model_refused: compile fp_model_probe.cpp (syntax only) with the default
# floating-point model, which must succeed, and under each option that breaks the
# kernel's arithmetic, which must fail with the kernel's own "rayproof: " #error
# (rayproof/detail/fp_model.hpp). Run by CTest in script mode:
#   cmake -DCXX=... -DCXX_ID=GNU|Clang -DPROBE=... -DINCLUDES="dir;dir" -P fp_model_refused.cmake
set(base ${CXX} -std=c++20 -fsyntax-only)
foreach(dir IN LISTS INCLUDES)
  list(APPEND base -I${dir})
endforeach()

function(compile expect_ok what)
  execute_process(COMMAND ${base} ${ARGN} ${PROBE} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(expect_ok AND NOT rc EQUAL 0)
    message(FATAL_ERROR "${what}: expected to compile, failed:\n${err}")
  endif()
  if(NOT expect_ok)
    if(rc EQUAL 0)
      message(FATAL_ERROR "${what}: compiled, but the kernel must refuse it")
    endif()
    if(NOT err MATCHES "rayproof: ")
      message(FATAL_ERROR "${what}: failed without the kernel's message:\n${err}")
    endif()
  endif()
  message(STATUS "${what}: as expected")
endfunction()

compile(TRUE "the default model")
# The escape hatch proves the refusal comes from the kernel's check and nothing else.
compile(TRUE "-ffast-math with RAYPROOF_ALLOW_UNSAFE_FP_MODEL" -ffast-math -DRAYPROOF_ALLOW_UNSAFE_FP_MODEL)

# What each compiler lets a header see (fp_model.hpp says which macros).
set(refused "-ffast-math" "-Ofast" "-ffinite-math-only")
if(CXX_ID STREQUAL "GNU")
  list(APPEND refused "-fassociative-math -fno-signed-zeros -fno-trapping-math" "-freciprocal-math"
                      "-fno-signed-zeros" "-funsafe-math-optimizations")
endif()
if(CXX_ID STREQUAL "Clang")
  list(APPEND refused "-ffp-model=fast")
endif()
# -Wfatal-errors: the kernel's #error must be the first error, and the compile stops
# there instead of parsing the rest of the kernel under the refused model.
foreach(flags IN LISTS refused)
  separate_arguments(args UNIX_COMMAND "${flags}")
  compile(FALSE "${flags}" -Wfatal-errors ${args})
endforeach()
