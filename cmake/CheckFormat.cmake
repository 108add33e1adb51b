# ctest's FormatCheck: the C++ sources must be as the committed .clang-format writes them
# (clang-format --dry-run --Werror lists every line it would change). Run as
#   cmake -DCLANG_FORMAT=/usr/bin/clang-format -DROOT=<source dir> -P CheckFormat.cmake
# The files are listed when the test runs, so a new file is checked without a re-configure.
# To fix: clang-format -i on the files named in the output.
file(GLOB_RECURSE files LIST_DIRECTORIES false
     "${ROOT}/include/*.h" "${ROOT}/plugin/*.h" "${ROOT}/plugin/*.cpp" "${ROOT}/plugin/*.inc"
     "${ROOT}/examples/*.h" "${ROOT}/examples/*.cpp" "${ROOT}/tests/*.h" "${ROOT}/tests/*.cpp")
list(SORT files)
execute_process(COMMAND "${CLANG_FORMAT}" --dry-run --Werror ${files}
                RESULT_VARIABLE status ERROR_VARIABLE report)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "${report}\nFormatCheck: the files above differ from .clang-format; "
                      "run clang-format -i on them.")
endif()
list(LENGTH files count)
message(STATUS "FormatCheck: ${count} files as .clang-format writes them")
