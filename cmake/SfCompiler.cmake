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

# Thin static archives: an archive names its objects instead of holding a
# copy of them. Debug objects are large, and a full copy in every archive
# doubled the disk a build tree needs. Archives are never installed.
foreach(lang C CXX)
  set(CMAKE_${lang}_ARCHIVE_CREATE "<CMAKE_AR> qcT <TARGET> <LINK_FLAGS> <OBJECTS>")
  set(CMAKE_${lang}_ARCHIVE_APPEND "<CMAKE_AR> qT <TARGET> <LINK_FLAGS> <OBJECTS>")
endforeach()

# Compressed debug sections (zlib) in objects and in what is linked from
# them: gdb, perf and the sanitizers' symbolizers read them as they are, and
# a debug build tree takes a third of the disk.
add_compile_options(-gz)
add_link_options(-gz)

# Unity builds (CMAKE_UNITY_BUILD, set by the presets: a module's sources are compiled as a few
# files that #include them, so the headers they share are parsed once per batch instead of once
# per source; a cold build takes a fraction of the time). GCC then sees the sources as headers and
# warns that a class uses a type of the anonymous namespace, a warning meant for real headers.
if(CMAKE_UNITY_BUILD AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  target_compile_options(sf_warnings INTERFACE -Wno-subobject-linkage)
endif()
