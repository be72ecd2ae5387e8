# Warnings, sanitizers and ccache for every smartfactory target.
find_program(SF_CCACHE ccache)
if(SF_CCACHE)
  set(CMAKE_C_COMPILER_LAUNCHER ${SF_CCACHE})
  set(CMAKE_CXX_COMPILER_LAUNCHER ${SF_CCACHE})
endif()

add_library(sf_warnings INTERFACE)
target_compile_options(sf_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wold-style-cast
  -Wcast-align -Woverloaded-virtual -Wconversion -Wsign-conversion
  -Wdouble-promotion -Wformat=2 -Wimplicit-fallthrough)
if(SF_WERROR)
  target_compile_options(sf_warnings INTERFACE -Werror)
endif()

if(SF_SANITIZE)
  add_compile_options(-fsanitize=${SF_SANITIZE} -fno-omit-frame-pointer -fno-sanitize-recover=all)
  add_link_options(-fsanitize=${SF_SANITIZE})
endif()
