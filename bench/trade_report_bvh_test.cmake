# bench.report.bvh: the report's "Tracer and BVH" tables come from the --bvh numbers, each
# row judged against its target (testdata/bvh_sample.txt: the 2,000-object render at
# 0.75× POV-Ray meets ≤ 1×; the 100,000-object render was stopped at 41 s, beyond 2× of
# 10 s; fast at 1.33× the faster Embree meets ≤ 1.5×; certified at 2.22× misses ≤ 2×; the
# double tree's row and build line, with no target).
#   cmake -DREPORT=rayproof_trade_report -DSAMPLE=bvh_sample.txt -DDIR=work -P trade_report_bvh_test.cmake
file(MAKE_DIRECTORY ${DIR})
file(WRITE ${DIR}/bench.json "{\"context\": {}, \"benchmarks\": []}")
execute_process(COMMAND ${REPORT} --bench ${DIR}/bench.json --bvh ${SAMPLE} --md ${DIR}/report.md
                RESULT_VARIABLE status OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "rayproof_trade_report failed (${status}): ${err}")
endif()
file(READ ${DIR}/report.md md)
foreach(expected
    "## Tracer and BVH"
    "| generated field | 2,000 | 1.5 | 2.75 | 2 | 3.5 | 0.75 | 0.786 | ≤ 1× | **yes** | 0.040/255 |"
    "| generated field | 100,000 | stopped at 41 | — | 10 | 18 | > 4.1 | — | ≤ 2× | **no** | — |"
    "| rayproof Bvh, fast | camera | 1.5 | 1.33 | 1 | ≤ 1.5× the faster Embree | **yes** |"
    "| rayproof Bvh, certified | camera | 0.9 | 2.22 | 1.67 | ≤ 2× the faster Embree | **no** |"
    "| Embree 3 | grazing | 100 | 96 | 7 | 2 | 1 | 4 |"
    "| rayproof Bvh, certified | grazing | 100 | 96 | 0 | 0 | 0 | 0 |"
    "| rayproof Bvh<float, 8> | 50 | 500 | 64 | 48 |"
    "| rayproof Bvh, double, certified | camera | 0.45 | 4.44 | 3.33 | — | — |"
    "| rayproof Bvh<double, 4> | 60 | 600 | 96 | 80 |")
  string(FIND "${md}" "${expected}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "the report lacks the line\n  ${expected}\nreport:\n${md}")
  endif()
endforeach()
