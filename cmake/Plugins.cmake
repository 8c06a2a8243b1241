# Plugin discovery. A method is a folder methods/<name>/ whose sources define
#   void mps_lab_register_method_<name>(mps_lab::MethodRegistry&);
# a wall treatment is one file core/walls/<name>.cpp defining
#   void mps_lab_register_wall_treatment_<name>(mps_lab::WallTreatmentRegistry&);
# This file generates the one function that calls them all, so adding a plugin means
# adding files, never editing a list in the core (and there is no static-initialisation
# registry, i.e. no global mutable state).

function(mps_lab_collect_wall_treatments dir out_decls out_calls)
  # A wall treatment is a file core/walls/<name>.cpp that defines its registration function;
  # the other files of core/walls/ (geometry, samples, the registry) are the walls' machinery.
  file(GLOB sources CONFIGURE_DEPENDS ${dir}/*.cpp)
  set(decls "")
  set(calls "")
  foreach(source IN LISTS sources)
    get_filename_component(name ${source} NAME_WE)
    file(STRINGS ${source} defines REGEX "^void mps_lab_register_wall_treatment_${name}\\(")
    if(NOT defines)
      continue()
    endif()
    string(APPEND decls "void mps_lab_register_wall_treatment_${name}(mps_lab::WallTreatmentRegistry&);\n")
    string(APPEND calls "  mps_lab_register_wall_treatment_${name}(registry);\n")
  endforeach()
  set(${out_decls} "${decls}" PARENT_SCOPE)
  set(${out_calls} "${calls}" PARENT_SCOPE)
endfunction()

function(mps_lab_collect_methods dir selection out_sources out_decls out_calls out_names)
  file(GLOB entries LIST_DIRECTORIES true CONFIGURE_DEPENDS ${dir}/*)
  set(sources "")
  set(decls "")
  set(calls "")
  set(names "")
  foreach(entry IN LISTS entries)
    if(NOT IS_DIRECTORY ${entry})
      continue()
    endif()
    get_filename_component(name ${entry} NAME)
    if(selection AND NOT name IN_LIST selection)
      continue()
    endif()
    file(GLOB method_sources CONFIGURE_DEPENDS ${entry}/*.cpp)
    if(NOT method_sources)
      continue()
    endif()
    list(APPEND sources ${method_sources})
    list(APPEND names ${name})
    string(APPEND decls "void mps_lab_register_method_${name}(mps_lab::MethodRegistry&);\n")
    string(APPEND calls "  mps_lab_register_method_${name}(registry);\n")
  endforeach()
  set(${out_sources} ${sources} PARENT_SCOPE)
  set(${out_decls} "${decls}" PARENT_SCOPE)
  set(${out_calls} "${calls}" PARENT_SCOPE)
  set(${out_names} "${names}" PARENT_SCOPE)
endfunction()
