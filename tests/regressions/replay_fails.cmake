# replay_fails.cmake — cmake -DPROGRAM=<replay executable> -DINPUT=<file> -DENV=<VAR=value>
# -P replay_fails.cmake: runs the replay on INPUT with the variable set and passes when
# the replay fails (non-zero status) reporting a contract violation.
execute_process(COMMAND ${CMAKE_COMMAND} -E env ${ENV} ${PROGRAM} ${INPUT}
                RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(status EQUAL 0 OR NOT err MATCHES "contract violation")
  message(FATAL_ERROR "with ${ENV} the replay of ${INPUT} passed (status ${status}), "
                      "so a triage filter let a failing input through:\n${out}${err}")
endif()
message(STATUS "with ${ENV} the replay still fails (status ${status})")
