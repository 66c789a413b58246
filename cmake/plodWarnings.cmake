# Warnings for this project's own code, shared by the main project and the ParaView plugin:
# -Wall -Wextra with GCC and Clang, and errors with PLOD_WARNINGS_AS_ERRORS (the test command,
# run by CI, sets it, so that no warning can creep in). Headers of VTK and ParaView come in as
# system headers and are not checked.
option(PLOD_WARNINGS_AS_ERRORS "Treat compiler warnings in this project's code as errors (CI)" OFF)
if (CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
  add_compile_options(-Wall -Wextra)
  if (PLOD_WARNINGS_AS_ERRORS)
    add_compile_options(-Werror)
  endif ()
endif ()
