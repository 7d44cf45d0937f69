# A power cut at every flash operation of a parameter save (test_power_cut.cpp): the real
# image build/stm32g4/dtc-fw.elf on the twin, cut by the twin's flash model; skips without the
# image. Four tests (into an empty slot / over an older set, clean / torn cut), a few minutes each.
set(DTC_STM32G4_BUILD_DIR ${CMAKE_SOURCE_DIR}/build/stm32g4 CACHE PATH
    "target build whose firmware libraries the twin's CANopen test image links")
add_executable(board_test_power_cut ${CMAKE_CURRENT_SOURCE_DIR}/test_power_cut.cpp)
target_link_libraries(board_test_power_cut PRIVATE board_twin hal_host GTest::gtest_main)
target_compile_definitions(board_test_power_cut PRIVATE DTC_STM32G4_BUILD_DIR="${DTC_STM32G4_BUILD_DIR}")
dtc_warnings(board_test_power_cut)
gtest_discover_tests(board_test_power_cut TEST_PREFIX "board." DISCOVERY_TIMEOUT 60
                     PROPERTIES LABELS board TIMEOUT 900)
