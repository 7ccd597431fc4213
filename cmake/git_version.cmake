# Run at every build (custom target dsdem_version): writes the version header with the
# commit the binary is built from, so logs and summary.json name the right commit
# (a configure-time value went stale with every later commit). configure_file only
# rewrites the header when the text changes, so an unchanged commit rebuilds nothing.
# Inputs: SOURCE_DIR, INPUT (version.hpp.in), OUTPUT.
execute_process(COMMAND git describe --always --dirty --abbrev=7 WORKING_DIRECTORY ${SOURCE_DIR}
                OUTPUT_VARIABLE DSDEM_GIT_COMMIT OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT DSDEM_GIT_COMMIT)
  set(DSDEM_GIT_COMMIT "unknown")
endif()
configure_file(${INPUT} ${OUTPUT} @ONLY)
