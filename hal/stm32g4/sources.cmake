# The STM32G474 binding's sources, relative to hal/stm32g4: the board file that implements
# hal/hal.h and the drivers it composes, one per peripheral. Read by hal/stm32g4/CMakeLists.txt
# (the images) and by tests/board (test images that link the binding on the host build).
set(DTC_STM32G4_DRIVER_SOURCES adc.c board_faults.c clock.c fdcan.c flash_nvm.c hrtim.c iwdg.c pins.c
    reset_cause.c)
set(DTC_STM32G4_BINDING_SOURCES hal_stm32g4.c ${DTC_STM32G4_DRIVER_SOURCES} npc_plan.c)
