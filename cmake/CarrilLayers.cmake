# Firmware layers that the build enforces. Each layer is one library whose sources see, through
# a generated include tree of symlinks, only their own folder, the folders of the layers they
# declare (transitively) and hal/: an include of a higher layer does not compile.
#
#   carril_firmware_layer(<name> [SOURCES a.cpp ...] [DEPENDS <layer> ...] [HAL])
#
# creates carril_fw_<name> for firmware/<name>/ (INTERFACE when it has no sources).

# The include tree <tree>: one symlink per path given, relative to the source root.
function(carril_include_tree tree)
  set(dir ${CMAKE_BINARY_DIR}/include-trees/${tree})
  foreach(path ${ARGN})
    get_filename_component(parent ${dir}/${path} DIRECTORY)
    file(MAKE_DIRECTORY ${parent})
    if(NOT EXISTS ${dir}/${path})
      file(CREATE_LINK ${PROJECT_SOURCE_DIR}/${path} ${dir}/${path} SYMBOLIC)
    endif()
  endforeach()
endfunction()

function(carril_firmware_layer name)
  cmake_parse_arguments(L "" "" "SOURCES;DEPENDS" ${ARGN})
  # The folders this layer may include: its own and everything its dependencies may.
  set(folders firmware/${name})
  foreach(dep ${L_DEPENDS})
    get_property(dep_folders GLOBAL PROPERTY carril_layer_folders_${dep})
    if(NOT dep_folders)
      message(FATAL_ERROR "firmware layer ${name}: layer ${dep} is not declared (yet)")
    endif()
    list(APPEND folders ${dep_folders})
  endforeach()
  list(REMOVE_DUPLICATES folders)
  set_property(GLOBAL PROPERTY carril_layer_folders_${name} ${folders})
  # "<name>:<dep>,<dep>" in declaration order, for the test that checks docs/architecture.md's
  # layer table against the build (tests/unit/app/LayersDocTest.cpp).
  string(REPLACE ";" "," dep_list "${L_DEPENDS}")
  set_property(GLOBAL APPEND PROPERTY carril_firmware_layers "${name}:${dep_list}")
  carril_include_tree(fw_${name} hal ${folders})
  set(tree ${CMAKE_BINARY_DIR}/include-trees/fw_${name})
  set(deps)
  foreach(dep ${L_DEPENDS})
    list(APPEND deps carril_fw_${dep})
  endforeach()
  if(L_SOURCES)
    add_library(carril_fw_${name} STATIC ${L_SOURCES})
    target_include_directories(carril_fw_${name} PUBLIC ${tree})
    target_link_libraries(carril_fw_${name}
      PUBLIC carril_hal Eigen3::Eigen carril_eigen_checks ${deps}
      PRIVATE carril_strict_warnings carril_no_exceptions)
  else()
    add_library(carril_fw_${name} INTERFACE)
    target_include_directories(carril_fw_${name} INTERFACE ${tree})
    target_link_libraries(carril_fw_${name} INTERFACE carril_hal Eigen3::Eigen carril_eigen_checks ${deps})
  endif()
  # Every header compiles on its own in this layer's tree, so a header no source of the layer
  # includes is held to the same rule.
  file(GLOB headers RELATIVE ${PROJECT_SOURCE_DIR}/firmware/${name}
       ${PROJECT_SOURCE_DIR}/firmware/${name}/*.hpp)
  set(checks)
  foreach(h ${headers})
    set(check ${CMAKE_BINARY_DIR}/header-checks/${name}/${h}.cpp)
    set(text "#include \"firmware/${name}/${h}\"\n")
    if(EXISTS ${check})
      file(READ ${check} old)
    endif()
    if(NOT EXISTS ${check} OR NOT old STREQUAL text)
      file(WRITE ${check} "${text}")
    endif()
    list(APPEND checks ${check})
  endforeach()
  if(checks)
    add_library(carril_fw_${name}_headers OBJECT ${checks})
    target_include_directories(carril_fw_${name}_headers PRIVATE ${tree})
    target_link_libraries(carril_fw_${name}_headers
      PRIVATE carril_hal Eigen3::Eigen carril_eigen_checks carril_strict_warnings
              carril_no_exceptions)
  endif()
endfunction()
