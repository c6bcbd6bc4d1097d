# Runs one libFuzzer target for the ctest label fuzz: -DFUZZER, -DCORPUS (a scratch corpus, new
# inputs go there), -DSEEDS (the seed corpus), -DRUNS (inputs). A fixed -seed makes the run repeat.
file(MAKE_DIRECTORY ${CORPUS})
execute_process(COMMAND ${FUZZER} -seed=1 -runs=${RUNS} -max_total_time=300 -timeout=25
                        -rss_limit_mb=4096 -max_len=8192 -print_final_stats=1
                        -artifact_prefix=${CORPUS}/ ${CORPUS} ${SEEDS}
                RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "${FUZZER} found a failing input (exit ${result}); it is saved in ${CORPUS}/")
endif()
