// The free-port example of L10403-10422: XMT 01 FF 00 01 02 on X0, then
// RCV 6 bytes; D100 counts replies ended by the maximum count (SD125 bit 2).
// Shared by test_aplc_ports.py (pyserial over a pty) and free.toml.
LD SM1
MOV 16#01 D0
MOV 16#FF D1
MOV 0 D2
MOV 1 D3
MOV 2 D4
LD X0
EU
RST SM122
XMT 1 D0 5
LD SM122
EU
RST SM123
RCV 1 D10 6
BLD SD125 2
AND SM123
EU
INC D100
