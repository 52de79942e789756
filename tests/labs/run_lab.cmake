# tests/labs/run_lab.cmake: runs a lab test program on a file that must FAIL the lab (the repository's
# untouched lab file, or the reference with one mistake put in), and checks that it fails the right
# way: exit status 1 (a diagnosis, not a crash: a signal or a sanitizer abort is not 1), the verdict
# line "K of M checks failed", every pattern in EXPECT (a ;-list of regular expressions: the hint
# that names the mistake), and with NO_OK, no part that passed (each part of the lab can fail).
#   cmake -DPROGRAM=... -DEXPECT=... [-DNO_OK=1] -P run_lab.cmake
execute_process(COMMAND ${PROGRAM} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(NOT rc STREQUAL "1")
  message(FATAL_ERROR "expected the lab to fail with exit status 1 (a diagnosis), got '${rc}'")
endif()
if(NOT out MATCHES "checks failed\n?$")
  message(FATAL_ERROR "no verdict line \"... K of M checks failed\" at the end")
endif()
foreach(pattern IN LISTS EXPECT)
  if(NOT out MATCHES "${pattern}")
    message(FATAL_ERROR "the lab's output does not name the mistake: no match for \"${pattern}\"")
  endif()
endforeach()
if(NO_OK AND out MATCHES "\\[ok\\]")
  message(FATAL_ERROR "a part of the lab passed on the untouched file: a check that cannot fail")
endif()
message("lab failed as expected, with a diagnosis")
