# Checks that the shards of an audit run, merged, equal the run: runs PROGRAM (rayproof-audit)
# once whole and as SHARDS shards (--shard K/N --save), merges them (--merge) and requires
# the same CSV report, the same Markdown report but for the timing part of its header line,
# and the same examples. Then checks that --merge refuses a missing shard, a shard given
# twice and a shard of another run. Files go to DIR.
#   cmake -DPROGRAM=... -DDIR=... -DSHARDS=3 -DARGS=--cases,40,--examples,2 -P shards.cmake
string(REPLACE "," ";" args "${ARGS}")
file(MAKE_DIRECTORY ${DIR})

function(run out_var status_var)
  execute_process(COMMAND ${PROGRAM} ${ARGN} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
  set(${out_var} "${out}" PARENT_SCOPE)
  set(${status_var} "${status}" PARENT_SCOPE)
  set(last_err "${err}" PARENT_SCOPE)
endfunction()

# The Markdown report without what differs between a run and a merge: the time and the
# shards, after the seed on the header line.
function(untimed text out_var)
  string(REGEX REPLACE "(seed 0x[0-9a-f]+;)[^\n]*" "\\1" text "${text}")
  set(${out_var} "${text}" PARENT_SCOPE)
endfunction()

foreach(format md csv)
  run(whole status ${args} --format ${format})
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "the whole run failed (${status}): ${last_err}")
  endif()
  set(files)
  foreach(k RANGE 1 ${SHARDS})
    set(f ${DIR}/shard-${k}-of-${SHARDS}.tsv)
    list(APPEND files ${f})
    run(ignored status ${args} --format ${format} --shard ${k}/${SHARDS} --save ${f})
    if(NOT status EQUAL 0)
      message(FATAL_ERROR "shard ${k}/${SHARDS} failed (${status}): ${last_err}")
    endif()
  endforeach()
  list(REVERSE files)  # the order of the files does not matter
  run(merged status --merge ${files} --format ${format})
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "--merge failed (${status}): ${last_err}")
  endif()
  if(format STREQUAL "md")
    untimed("${whole}" whole)
    untimed("${merged}" merged)
  endif()
  if(NOT whole STREQUAL merged)
    file(WRITE ${DIR}/whole.${format} "${whole}")
    file(WRITE ${DIR}/merged.${format} "${merged}")
    message(FATAL_ERROR "${SHARDS} shards merged differ from the whole run (${format}): "
                        "diff ${DIR}/whole.${format} ${DIR}/merged.${format}")
  endif()
  string(LENGTH "${whole}" n)
  message(STATUS "${format}: ${SHARDS} shards merged equal the whole run (${n} characters)")
endforeach()

# --merge refuses what is not the shards 1..N of one run, naming the problem.
list(GET files 0 one)
list(GET files 1 two)
run(other status --cases 3 --shape plane --shard 1/${SHARDS} --save ${DIR}/other.tsv)
set(cases_missing "${one}" "${two}" "missing")
set(cases_twice "${one}" "${one}" "is in both")
set(cases_other "${files}" "${DIR}/other.tsv" "another run")
foreach(c missing twice other)
  set(given ${cases_${c}})
  list(POP_BACK given expected)
  run(ignored status --merge ${given})
  string(FIND "${last_err}" "${expected}" at)
  if(NOT status EQUAL 1 OR at EQUAL -1)
    message(FATAL_ERROR "--merge of ${c} shards: expected exit status 1 and '${expected}', got ${status}: ${last_err}")
  endif()
endforeach()
message(STATUS "--merge refuses a missing shard, a shard given twice and another run's shard")
