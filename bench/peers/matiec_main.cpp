// Runs a matiec-generated configuration (Config0.c, Res0.c) for N cycles the
// way OpenPLC's runtime drives it (webserver/core/main.cpp): config_init__()
// once, then per cycle config_run__(tick++) and the PLC clock advanced by one
// task period. There is no sleep between cycles and no I/O: only the program
// is timed. measure.py compiles this beside the generated C (README.md).
//
// Usage: plc CYCLES
#include <stdio.h>
#include <stdlib.h>

#include "iec_std_lib.h"

TIME __CURRENT_TIME;
BOOL __DEBUG;
extern unsigned long long common_ticktime__;
void config_init__(void);
void config_run__(unsigned long tick);

int main(int argc, char **argv) {
    if (argc != 2) {
        fprintf(stderr, "usage: %s CYCLES\n", argv[0]);
        return 2;
    }
    unsigned long cycles = strtoul(argv[1], NULL, 10);
    config_init__();
    for (unsigned long tick = 0; tick < cycles; tick++) {
        config_run__(tick);
        // The clock advances by the task period, as OpenPLC's updateTime().
        __CURRENT_TIME.tv_nsec += common_ticktime__;
        while (__CURRENT_TIME.tv_nsec >= 1000000000) {
            __CURRENT_TIME.tv_nsec -= 1000000000;
            __CURRENT_TIME.tv_sec += 1;
        }
    }
    return 0;
}
