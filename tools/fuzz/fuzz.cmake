# Fuzzing build, clang only:
#   CC=clang CXX=clang++ cmake -S . -B build-fuzz -DNFRC_FUZZ=ON [-DNFRC_BUILD_TESTS=OFF]
# then tools/fuzz/run_fuzz.sh SECONDS. Every target gets libFuzzer's coverage instrumentation
# and ASan + UBSan; a UB report aborts (no recovery) so that libFuzzer counts it as a crash,
# and assertions stay on (Eigen's index checks, nlohmann's JSON_ASSERT) so a failed one is a
# finding. -O1 with line tables only: the usual fuzzing trade-off (fast enough, stacks with
# file and line; full debug information adds compile time and object size, not stack detail).
option(NFRC_FUZZ "Build tools/fuzz/case_reader_fuzzer (clang, libFuzzer, ASan, UBSan)" OFF)
if(NFRC_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "NFRC_FUZZ needs clang: configure with CC=clang CXX=clang++")
  endif()
  if(NFRC_SANITIZE)
    message(FATAL_ERROR "NFRC_FUZZ already enables ASan and UBSan: leave NFRC_SANITIZE off")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all
                      -fno-omit-frame-pointer -gline-tables-only -O1 -UNDEBUG)
  add_link_options(-fsanitize=address,undefined)
  add_subdirectory(${CMAKE_CURRENT_LIST_DIR} ${CMAKE_BINARY_DIR}/fuzz)
endif()
