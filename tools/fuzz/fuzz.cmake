# Fuzzing build, clang only:
#   CC=clang CXX=clang++ cmake -S . -B build-fuzz -DNFRC_FUZZ=ON [-DNFRC_SANITIZE=ON]
# then tools/fuzz/run_fuzz.sh SECONDS. Every target gets ASan + UBSan; a UB report aborts (no
# recovery) so that libFuzzer counts it as a crash, and assertions stay on (nfrc's invariants,
# Eigen's index checks, nlohmann's JSON_ASSERT) so a failed one is a finding. -O1 with line
# tables only: the usual fuzzing trade-off (fast enough, stacks with file and line).
#
# libFuzzer's coverage instrumentation goes only to the sources the fuzzer reads and checks
# a case with (coverage_allowlist.txt): it guides mutations towards new reading paths, and
# left off the dense algebra it costs the tests nothing. With NFRC_SANITIZE as well the same
# tree runs the test suite under the sanitizers (CI builds one instrumented tree, not two).
option(NFRC_FUZZ "Build tools/fuzz/case_reader_fuzzer (clang, libFuzzer, ASan, UBSan)" OFF)
if(NFRC_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "NFRC_FUZZ needs clang: configure with CC=clang CXX=clang++")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined
                      -fsanitize-coverage-allowlist=${CMAKE_CURRENT_LIST_DIR}/coverage_allowlist.txt
                      -fno-sanitize-recover=all -fno-omit-frame-pointer -gline-tables-only -O1
                      -UNDEBUG)
  add_link_options(-fsanitize=address,undefined)
  add_subdirectory(${CMAKE_CURRENT_LIST_DIR} ${CMAKE_BINARY_DIR}/fuzz)
endif()
