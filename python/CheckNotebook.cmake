# Executes a notebook with `jupyter nbconvert --execute` (run by CTest as
# Notebook.*): every cell must run without an error, its asserts included.
# Skips where nbconvert or ipykernel is missing (Debian: python3-nbconvert,
# python3-ipykernel; scripts/setup.sh installs them).
# Usage: cmake -DPYTHON=... -DNOTEBOOK=... -DOUT_DIR=... -P CheckNotebook.cmake
execute_process(COMMAND ${PYTHON} -c "import nbconvert, ipykernel" RESULT_VARIABLE _rc OUTPUT_QUIET ERROR_QUIET)
if(NOT _rc EQUAL 0)
  message("SKIP: ${PYTHON} cannot import nbconvert and ipykernel (install python3-nbconvert python3-ipykernel)")
  return()
endif()
file(REMOVE_RECURSE ${OUT_DIR})
file(MAKE_DIRECTORY ${OUT_DIR})
# The kernel is this interpreter's own (ipykernel's python3 kernel runs sys.executable).
execute_process(COMMAND ${PYTHON} -m nbconvert --to notebook --execute --ExecutePreprocessor.timeout=300
                        --output-dir ${OUT_DIR} ${NOTEBOOK}
                RESULT_VARIABLE _rc OUTPUT_VARIABLE _out ERROR_VARIABLE _out)
if(NOT _rc EQUAL 0)
  message(FATAL_ERROR "nbconvert --execute ${NOTEBOOK} failed (${_rc}):\n${_out}")
endif()
message("executed ${NOTEBOOK} into ${OUT_DIR}")
