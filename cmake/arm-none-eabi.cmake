# Toolchain: arm-none-eabi-gcc for the Cortex-M4F (STM32G474 class).
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)
set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_CXX_COMPILER arm-none-eabi-g++)
set(CMAKE_ASM_COMPILER arm-none-eabi-gcc)
set(CMAKE_OBJCOPY arm-none-eabi-objcopy CACHE FILEPATH "")
set(CMAKE_SIZE arm-none-eabi-size CACHE FILEPATH "")
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

set(DTC_CPU_FLAGS "-mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard")
# DTC_EXTRA_C_FLAGS (-D at a first configure; none when not given): C flags
# added to these, for measuring compiler options (tools/pil_bench.sh's
# DTC_PIL_CFLAGS builds into its own directory with them).
set(CMAKE_C_FLAGS_INIT "${DTC_CPU_FLAGS} -ffunction-sections -fdata-sections -fno-math-errno -fsingle-precision-constant ${DTC_EXTRA_C_FLAGS}")
set(CMAKE_CXX_FLAGS_INIT "${DTC_CPU_FLAGS} -ffunction-sections -fdata-sections")
set(CMAKE_ASM_FLAGS_INIT "${DTC_CPU_FLAGS}")
set(CMAKE_EXE_LINKER_FLAGS_INIT "${DTC_CPU_FLAGS} -Wl,--gc-sections --specs=nano.specs --specs=nosys.specs")

set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
