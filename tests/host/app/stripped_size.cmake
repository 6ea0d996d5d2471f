# cmake -DSTRIP=strip -DBINARY=file -DOUT=file -DMAX_BYTES=N -P stripped_size.cmake: strips BINARY
# into OUT and fails when OUT is larger than MAX_BYTES (the issue's 8 MB for the board's daemon).
execute_process(COMMAND ${STRIP} -o ${OUT} ${BINARY} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${STRIP} ${BINARY} failed (${rc})")
endif()
file(SIZE ${OUT} bytes)
message("stripped ${BINARY}: ${bytes} bytes (at most ${MAX_BYTES})")
if(bytes GREATER MAX_BYTES)
  message(FATAL_ERROR "stripped daemon is ${bytes} bytes, over ${MAX_BYTES}")
endif()
