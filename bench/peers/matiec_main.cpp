// Runs a matiec-generated configuration (Config0.c, Res0.c) for N cycles the
// way OpenPLC's runtime drives it (webserver/core/main.cpp): config_init__()
// once, then per cycle config_run__(tick++) and the PLC clock advanced by one
// task period. There is no sleep between cycles and no I/O: only the program
// is timed. measure.py compiles this beside the generated C (README.md).
//
// Usage: plc CYCLES [show]
//   show: print D0, D1 and D1999 after the cycles (built with -DSHOW_MIX,
//   the mix workload's program instance).
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "iec_std_lib.h"
#ifdef SHOW_MIX
#include "POUS.h"
extern MIX_PROG RES0__INSTANCE0;
#endif

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
#ifdef SHOW_MIX
    if (argc == 3 && strcmp(argv[2], "show") == 0) {
        printf("D0 = %d\nD1 = %d\nD1999 = %d\n", RES0__INSTANCE0.D0.value, RES0__INSTANCE0.D1.value,
               RES0__INSTANCE0.D1999.value);
    }
#endif
    return 0;
}
