# Finds SuiteSparse's CHOLMOD (Debian's libsuitesparse-dev ships no CMake config) and
# defines the imported target Cholmod::Cholmod.
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse REQUIRED)
find_library(CHOLMOD_LIBRARY cholmod REQUIRED)
find_library(SUITESPARSECONFIG_LIBRARY suitesparseconfig REQUIRED)
find_library(AMD_LIBRARY amd REQUIRED)
find_library(CAMD_LIBRARY camd REQUIRED)
find_library(COLAMD_LIBRARY colamd REQUIRED)
find_library(CCOLAMD_LIBRARY ccolamd REQUIRED)
add_library(Cholmod::Cholmod INTERFACE IMPORTED)
target_include_directories(Cholmod::Cholmod INTERFACE ${CHOLMOD_INCLUDE_DIR})
target_link_libraries(Cholmod::Cholmod INTERFACE ${CHOLMOD_LIBRARY} ${AMD_LIBRARY} ${CAMD_LIBRARY}
  ${COLAMD_LIBRARY} ${CCOLAMD_LIBRARY} ${SUITESPARSECONFIG_LIBRARY})
