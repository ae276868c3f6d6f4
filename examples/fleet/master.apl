// Line master (APLC-TCP): a Modbus RTU master on PORT1 polling the tank
// PLC (station 2) in turn: FC 03 reads its level (holding register 0, its
// D0) into D100..D104, FC 06 writes the setpoint D200 into its register 1
// (its D1). Each completion (SM135 done or SM136 error) moves D50 to the
// next request; a request starts on the rising edge of its power flow,
// when the port is idle (SM124).
LD SM1
MOV 2 D0            // station 2
MOV 3 D1            // FC 03 read holding registers
MOV 0 D2            // start high, low: register 0
MOV 0 D3
MOV 0 D4            // quantity high, low: 1
MOV 1 D5
MOV 2 D10           // station 2
MOV 6 D11           // FC 06 write single register
MOV 0 D12           // register high, low: 1
MOV 1 D13
// The setpoint's bytes: high D14, low D15 (DIV's quotient and remainder).
LD SM0
DIV D200 256 D14
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
Modbus 1 D10 D120
// The reply: D100 station, D101 FC, D102 byte count, D103 and D104 the
// register's bytes; the level in mm is D103 * 256 + D104 (MUL: D300 high,
// D301 low).
LD SM0
MUL D103 256 D300
ADD D301 D104 D302
// A failed poll counts in D60 (SD139 keeps its code).
LD SM136
EU
INC D60
