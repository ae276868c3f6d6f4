// Modbus master on PORT1 (the APLC manual's Modbus instruction, §6.10.1): a
// drive (station 1) and an energy meter (station 2) on one RS-485 line,
// polled in turn with FC 03. Each completion (SM135 done or SM136 error)
// moves D50 to the next slave; a request starts on the rising edge of its
// power flow, when the port is idle (SM124).
// Drive: registers 0-1 = status word, actual speed (rpm) → D100..D106.
// Meter: registers 0-3 = voltage (V), current (0.1 A), power (W, 32-bit
// high word first) → D200..D210. The reply is one byte per word.
LD SM1
MOV 1 D0            // station 1
MOV 3 D1            // FC 03 read holding registers
MOV 0 D2            // start high, low
MOV 0 D3
MOV 0 D4            // quantity high, low: 2
MOV 2 D5
MOV 2 D10           // station 2
MOV 3 D11
MOV 0 D12
MOV 0 D13
MOV 0 D14
MOV 4 D15           // 4 registers
LD SM135
OR SM136
EU
INC D50
LD>= D50 2
MOV 0 D50
LD SM124
AND= D50 0
Modbus 1 D0 D100
LD SM124
AND= D50 1
Modbus 1 D10 D200
// The reply: D100 station, D101 FC, D102 byte count, then the bytes; the
// drive's speed (register 1) is D105 * 256 + D106 (MUL: D300 high, D301 low).
LD SM0
MUL D105 256 D300
ADD D301 D106 D302
// A failed poll counts in D60 (SD139 keeps its code).
LD SM136
EU
INC D60
