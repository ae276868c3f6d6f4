// Runs a matiec-generated configuration (Config0.c, Res0.c) for N cycles the
// way OpenPLC's runtime drives it (webserver/core/main.cpp): config_init__()
// once, then per cycle config_run__(tick++) and the PLC clock advanced by one
// task period. There is no sleep between cycles and no I/O: only the program
// is timed. measure.py compiles this beside the generated C (README.md).
//
// Usage: plc CYCLES [show]
//   show: print the workload's checked values after the cycles; measure.py
//   writes show.h beside the generated C with show_values(), which reads
//   them from the program instance.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "iec_std_lib.h"
#include "show.h"

TIME __CURRENT_TIME;
BOOL __DEBUG;
extern unsigned long long common_ticktime__;
void config_init__(void);
void config_run__(unsigned long tick);

// OpenPLC's headers define the TCP function blocks inline on top of its
// runtime's socket layer (openplc_networking.h); without optimisation the
// compiler keeps those bodies, so the linker needs the layer. The workloads
// use no TCP block: these fail every call, as a runtime without sockets would.
int connect_to_tcp_server(uint8_t *, uint16_t, int) { return -1; }
int send_tcp_message(uint8_t *, size_t, int) { return -1; }
int receive_tcp_message(uint8_t *, size_t, int) { return -1; }
int close_tcp_connection(int) { return -1; }

int main(int argc, char **argv) {
    if (argc < 2 || argc > 3) {
        fprintf(stderr, "usage: %s CYCLES [show]\n", argv[0]);
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
    if (argc == 3 && strcmp(argv[2], "show") == 0) {
        show_values();
    }
    return 0;
}
