# cmake -DEXAMPLE=... -DCALIBENCH=... -DPOINTS=... -DWORK_DIR=... -P same_calibration_text.cmake
# Runs the example and `calibench calibrate --points POINTS --model pinhole-k2 --skew` and fails
# unless both print the same calibration text. Only the wall times ("12.3 ms") may differ.
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
execute_process(COMMAND "${EXAMPLE}" "${POINTS}" RESULT_VARIABLE example_rc
                OUTPUT_VARIABLE example_text ERROR_QUIET)
execute_process(COMMAND "${CALIBENCH}" calibrate --points "${POINTS}" --model pinhole-k2 --skew
                        --out "${WORK_DIR}/camera.yaml"
                RESULT_VARIABLE cli_rc OUTPUT_VARIABLE cli_text ERROR_QUIET)
if(NOT example_rc EQUAL 0 OR NOT cli_rc EQUAL 0)
  message(FATAL_ERROR "exit codes: example ${example_rc}, calibench calibrate ${cli_rc}")
endif()
foreach(text example_text cli_text)
  string(REGEX REPLACE "[0-9.]+ ms" "<t> ms" ${text} "${${text}}")
endforeach()
if(example_text STREQUAL "")
  message(FATAL_ERROR "the example printed nothing")
endif()
if(NOT example_text STREQUAL cli_text)
  file(WRITE "${WORK_DIR}/example.txt" "${example_text}")
  file(WRITE "${WORK_DIR}/calibench.txt" "${cli_text}")
  message(FATAL_ERROR "the texts differ: diff ${WORK_DIR}/example.txt ${WORK_DIR}/calibench.txt")
endif()
message(STATUS "same calibration text (${POINTS})")
