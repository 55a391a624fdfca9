# SPDX-License-Identifier: BSL-1.0
# Runs site_hash and keeps its lines. Host: -DPROGRAM -DMASK_DIR -DOUTPUT -DPNGS="a.png;b.png"
# (writes the PGM copies into MASK_DIR). Cross target: also -DEMULATOR and -DREFERENCE, the
# host's lines, which must be equal.
if(DEFINED PNGS)
  file(MAKE_DIRECTORY "${MASK_DIR}")
  execute_process(COMMAND "${PROGRAM}" --pgm "${MASK_DIR}" ${PNGS}
                  OUTPUT_FILE "${OUTPUT}" RESULT_VARIABLE status)
else()
  if(NOT EXISTS "${REFERENCE}")
    message(FATAL_ERROR "site_hash: no host reference ${REFERENCE}: run the test workflow first")
  endif()
  file(GLOB masks "${MASK_DIR}/*.pgm")
  execute_process(COMMAND ${EMULATOR} "${PROGRAM}" ${masks}
                  OUTPUT_FILE "${OUTPUT}" RESULT_VARIABLE status)
endif()
if(NOT status EQUAL 0)
  message(FATAL_ERROR "site_hash failed (${status})")
endif()
file(READ "${OUTPUT}" lines)
message("${lines}")
if(DEFINED REFERENCE)
  file(READ "${REFERENCE}" expected)
  if(NOT lines STREQUAL expected)
    message(FATAL_ERROR "site_hash: sites differ from the host's (${REFERENCE})")
  endif()
endif()
