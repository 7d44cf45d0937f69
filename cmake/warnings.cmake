# Warning sets. Everything builds with -Wall -Wextra -Werror; the portable
# firmware additionally refuses silent float->double promotion and implicit
# narrowing, because on the Cortex-M4F a stray double is a software call.
set(DTC_WARNINGS -Wall -Wextra -Werror)
set(DTC_FIRMWARE_WARNINGS ${DTC_WARNINGS} -Wdouble-promotion -Wconversion -Wshadow -Wstrict-prototypes)

function(dtc_warnings target)
  target_compile_options(${target} PRIVATE ${DTC_WARNINGS})
endfunction()

function(dtc_firmware_warnings target)
  target_compile_options(${target} PRIVATE $<$<COMPILE_LANGUAGE:C>:${DTC_FIRMWARE_WARNINGS}>)
endfunction()
