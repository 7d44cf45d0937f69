# FDCAN1 on the twin (host_sim/board/src/fdcan*.c) with small test images built here by
# arm-none-eabi-gcc (the host build needs no target preset):
#   can_drv_<rate>.elf   the port's own CAN driver (hal/stm32g4/fdcan.c, with the clock tree,
#                        the pin map and the fault word it needs) at 170 MHz,
#                        fdcan_open(<rate>), one frame out, then an echo of every frame in
#   can_model_<n>.elf    register-level checks (case 0) and one wrong use per case (1..9)
# and, where the twin runs it far enough, the real image build/stm32g4/dtc-fw.elf.
find_program(DTC_ARM_GCC arm-none-eabi-gcc)
if(NOT DTC_ARM_GCC)
  message(STATUS "board CAN tests: arm-none-eabi-gcc not found, not registered")
  return()
endif()

set(BCAN_OUT ${CMAKE_CURRENT_BINARY_DIR}/images)
set(BCAN_SRC ${CMAKE_CURRENT_SOURCE_DIR}/images)
set(BCAN_HAL ${CMAKE_SOURCE_DIR}/hal/stm32g4)
set(BCAN_FLAGS -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard -O2 -ffunction-sections
    -fdata-sections -fno-math-errno -fsingle-precision-constant -Wall -Wextra -Werror
    -I${CMAKE_SOURCE_DIR}/hal/include -I${BCAN_HAL}
    -I${CMAKE_SOURCE_DIR}/firmware/control/include) # dtc/npc.h: the leg planner's leg codes and rule
set(BCAN_LINK -T${BCAN_HAL}/stm32g474.ld -nostartfiles -Wl,--gc-sections --specs=nano.specs --specs=nosys.specs)

# The port's vector table and reset handler; each image brings the board_init() it needs.
add_custom_command(OUTPUT ${BCAN_OUT}/startup_test.o
  COMMAND ${CMAKE_COMMAND} -E make_directory ${BCAN_OUT}
  COMMAND ${DTC_ARM_GCC} ${BCAN_FLAGS} -c ${BCAN_HAL}/startup_stm32g474.c -o ${BCAN_OUT}/startup_test.o
  DEPENDS ${BCAN_HAL}/startup_stm32g474.c ${BCAN_HAL}/board.h ${BCAN_HAL}/stm32g474_regs.h
  VERBATIM)

# The CAN driver and what it calls: the clock tree and time base, the pins, the fault word.
set(BCAN_DRIVER ${BCAN_HAL}/fdcan.c ${BCAN_HAL}/clock.c ${BCAN_HAL}/pins.c ${BCAN_HAL}/board_faults.c)
file(GLOB BCAN_HEADERS CONFIGURE_DEPENDS ${BCAN_HAL}/*.h)
set(BCAN_IMAGES)
foreach(rate 125000 250000 500000 1000000)
  set(elf ${BCAN_OUT}/can_drv_${rate}.elf)
  add_custom_command(OUTPUT ${elf}
    COMMAND ${DTC_ARM_GCC} ${BCAN_FLAGS} -DCAN_BITRATE=${rate}u ${BCAN_SRC}/can_driver_image.c
            ${BCAN_DRIVER} ${BCAN_OUT}/startup_test.o ${BCAN_LINK} -o ${elf}
    DEPENDS ${BCAN_SRC}/can_driver_image.c ${BCAN_SRC}/semihost_min.h ${BCAN_DRIVER} ${BCAN_HEADERS}
            ${BCAN_HAL}/stm32g474.ld ${BCAN_OUT}/startup_test.o
    VERBATIM)
  list(APPEND BCAN_IMAGES ${elf})
endforeach()
foreach(case RANGE 0 9)
  set(elf ${BCAN_OUT}/can_model_${case}.elf)
  add_custom_command(OUTPUT ${elf}
    COMMAND ${DTC_ARM_GCC} ${BCAN_FLAGS} -DCASE=${case} ${BCAN_SRC}/can_model_image.c
            ${BCAN_OUT}/startup_test.o ${BCAN_LINK} -o ${elf}
    DEPENDS ${BCAN_SRC}/can_model_image.c ${BCAN_SRC}/semihost_min.h ${BCAN_HAL}/stm32g474.ld
            ${BCAN_OUT}/startup_test.o
    VERBATIM)
  list(APPEND BCAN_IMAGES ${elf})
endforeach()
# The real drive + CANopen firmware (the libraries of the target build) with the port's whole
# binding, started without the watchdog and the control tick. Needs the stm32g4 preset built
# first; without it the test skips and says so.
set(DTC_STM32G4_BUILD_DIR ${CMAKE_SOURCE_DIR}/build/stm32g4 CACHE PATH
    "target build whose firmware libraries the twin's CANopen test image links")
set(BCAN_FWLIBS ${DTC_STM32G4_BUILD_DIR}/firmware/libdtc_drive.a ${DTC_STM32G4_BUILD_DIR}/firmware/libdtc_control.a
    ${DTC_STM32G4_BUILD_DIR}/firmware/libdtc_canopen.a)
set(BCAN_HAVE_FW ON)
foreach(lib ${BCAN_FWLIBS} ${DTC_STM32G4_BUILD_DIR}/generated/include/dtc/param_table.h)
  if(NOT EXISTS ${lib})
    set(BCAN_HAVE_FW OFF)
  endif()
endforeach()
if(BCAN_HAVE_FW)
  set(elf ${BCAN_OUT}/canopen_image.elf)
  include(${BCAN_HAL}/sources.cmake)
  list(TRANSFORM DTC_STM32G4_BINDING_SOURCES PREPEND ${BCAN_HAL}/ OUTPUT_VARIABLE BCAN_BINDING)
  add_custom_command(OUTPUT ${elf}
    COMMAND ${DTC_ARM_GCC} ${BCAN_FLAGS} -I${CMAKE_SOURCE_DIR}/firmware/drive/include
            -I${CMAKE_SOURCE_DIR}/firmware/canopen/include -I${CMAKE_SOURCE_DIR}/firmware/control/include
            -I${DTC_STM32G4_BUILD_DIR}/generated/include ${BCAN_SRC}/canopen_image.c ${BCAN_BINDING}
            ${BCAN_OUT}/startup_test.o -Wl,--start-group ${BCAN_FWLIBS} -lm -Wl,--end-group ${BCAN_LINK} -o ${elf}
    DEPENDS ${BCAN_SRC}/canopen_image.c ${BCAN_SRC}/semihost_min.h ${BCAN_BINDING} ${BCAN_HEADERS} ${BCAN_FWLIBS}
            ${BCAN_HAL}/stm32g474.ld ${BCAN_OUT}/startup_test.o
    VERBATIM)
  list(APPEND BCAN_IMAGES ${elf})
else()
  message(STATUS "board CAN tests: no target firmware libraries in ${DTC_STM32G4_BUILD_DIR} (build the stm32g4 preset,"
                 " then re-run cmake --preset host): the CANopen image test will skip")
endif()
add_custom_target(board_can_images ALL DEPENDS ${BCAN_IMAGES})

add_executable(board_test_fdcan ${CMAKE_CURRENT_SOURCE_DIR}/test_fdcan.cpp)
target_link_libraries(board_test_fdcan PRIVATE board_twin hal_host GTest::gtest_main)
target_compile_definitions(board_test_fdcan PRIVATE
  DTC_SOURCE_DIR="${CMAKE_SOURCE_DIR}" DTC_BINARY_DIR="${CMAKE_BINARY_DIR}" BCAN_IMAGES="${BCAN_OUT}"
  DTC_BOARD_EXE="$<TARGET_FILE:dtc-board>")
add_dependencies(board_test_fdcan board_can_images dtc-board)
dtc_warnings(board_test_fdcan)
gtest_discover_tests(board_test_fdcan TEST_PREFIX "board." DISCOVERY_TIMEOUT 60
                     WORKING_DIRECTORY ${CMAKE_BINARY_DIR} PROPERTIES LABELS board)

# The same image on real SocketCAN: dtc-board exec --can vcan0, inside User-Mode Linux where
# the host kernel has no CAN (tests/can/uml/run_in_uml.sh runs directly where vcan exists).
if(NOT DTC_SANITIZE)
  add_test(NAME board.can_socketcan_uml
           COMMAND ${CMAKE_SOURCE_DIR}/tests/can/uml/run_in_uml.sh --timeout 120 --
                   ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/test_can_socketcan.py
                   $<TARGET_FILE:dtc-board> ${BCAN_OUT}/can_drv_500000.elf)
  set_tests_properties(board.can_socketcan_uml PROPERTIES LABELS board TIMEOUT 240 RUN_SERIAL TRUE)
endif()

# dtctune sessions against the twin running the flashable image build/stm32g4/dtc-fw.elf over
# SocketCAN (tests/board/test_twin_dtctune.py): get, set, read back, save, power-cycle (a new
# dtc-board on the same --nvm file), get, restore defaults, power-cycle, get.
# Needs the venv (tools/setup_venv.sh, run first here); skips (77) without the image.
if(NOT DTC_SANITIZE)
  set(BCAN_FW_ELF ${DTC_STM32G4_BUILD_DIR}/dtc-fw.elf)
  add_test(NAME board.twin_dtctune_uml
           COMMAND sh -c "${CMAKE_SOURCE_DIR}/tools/setup_venv.sh >/dev/null && exec ${CMAKE_SOURCE_DIR}/tests/can/uml/run_in_uml.sh --timeout 240 -- ${CMAKE_SOURCE_DIR}/.venv/bin/python ${CMAKE_CURRENT_SOURCE_DIR}/test_twin_dtctune.py tune $<TARGET_FILE:dtc-board> ${BCAN_FW_ELF} ${CMAKE_BINARY_DIR}/drive.eds ${CMAKE_CURRENT_BINARY_DIR}/twin-tune")
  set_tests_properties(board.twin_dtctune_uml PROPERTIES LABELS board TIMEOUT 330 RUN_SERIAL TRUE SKIP_RETURN_CODE 77)
  # Watchdog: the test-only build dtc-fw-stalltest.elf stops its control tick 300 ms after a
  # power-on; the twin's IWDG resets it; it boots with the saved parameters, sends EMCY 0x6010
  # and reports reset_cause 4 (0x2510:7), checked from a second node on vcan0.
  add_test(NAME board.watchdog_uml
           COMMAND sh -c "${CMAKE_SOURCE_DIR}/tools/setup_venv.sh >/dev/null && exec ${CMAKE_SOURCE_DIR}/tests/can/uml/run_in_uml.sh --timeout 240 -- ${CMAKE_SOURCE_DIR}/.venv/bin/python ${CMAKE_CURRENT_SOURCE_DIR}/test_twin_dtctune.py watchdog $<TARGET_FILE:dtc-board> ${BCAN_FW_ELF} ${CMAKE_BINARY_DIR}/drive.eds ${CMAKE_CURRENT_BINARY_DIR}/twin-watchdog ${DTC_STM32G4_BUILD_DIR}/dtc-fw-stalltest.elf")
  set_tests_properties(board.watchdog_uml PROPERTIES LABELS board TIMEOUT 330 RUN_SERIAL TRUE SKIP_RETURN_CODE 77)
  # Tuning while the emulated motor runs: dtc-board run CASE2 --can vcan0 --realtime, dtctune
  # get/set/read back (and a stopped-only setting refused) during the run.
  add_test(NAME board.twin_running_uml
           COMMAND sh -c "${CMAKE_SOURCE_DIR}/tools/setup_venv.sh >/dev/null && exec ${CMAKE_SOURCE_DIR}/tests/can/uml/run_in_uml.sh --timeout 300 -- ${CMAKE_SOURCE_DIR}/.venv/bin/python ${CMAKE_CURRENT_SOURCE_DIR}/test_twin_dtctune.py running $<TARGET_FILE:dtc-board> ${BCAN_FW_ELF} ${CMAKE_BINARY_DIR}/drive.eds ${CMAKE_CURRENT_BINARY_DIR}/twin-running ${CMAKE_SOURCE_DIR}/host_sim/scenarios/case2.ini")
  set_tests_properties(board.twin_running_uml PROPERTIES LABELS board TIMEOUT 390 RUN_SERIAL TRUE SKIP_RETURN_CODE 77)
  # --realtime keeps the bus's time: the heartbeat period (0x1017 = 100 ms) measured from the
  # frames' receive timestamps on vcan0 while dtc-board run CASE2 (as shipped) runs.
  add_test(NAME board.twin_heartbeat_uml
           COMMAND sh -c "${CMAKE_SOURCE_DIR}/tools/setup_venv.sh >/dev/null && exec ${CMAKE_SOURCE_DIR}/tests/can/uml/run_in_uml.sh --timeout 300 -- ${CMAKE_SOURCE_DIR}/.venv/bin/python ${CMAKE_CURRENT_SOURCE_DIR}/test_twin_dtctune.py heartbeat $<TARGET_FILE:dtc-board> ${BCAN_FW_ELF} ${CMAKE_BINARY_DIR}/drive.eds ${CMAKE_CURRENT_BINARY_DIR}/twin-heartbeat ${CMAKE_SOURCE_DIR}/host_sim/scenarios/case2.ini")
  set_tests_properties(board.twin_heartbeat_uml PROPERTIES LABELS board TIMEOUT 390 RUN_SERIAL TRUE SKIP_RETURN_CODE 77)
endif()
