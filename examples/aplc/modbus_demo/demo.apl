// Master of a MELSEC-Q `softplc serve … --modbus-rtu` at station 1 (its
// default map: holding register n = Dn). On SM12's rising edge (1 s clock)
// read Q's D0 (FC 03, 1 register) into D100..D104; on its falling edge
// write Q's D100 = D70 (FC 06), the count of completed transactions.
LD SM1
MOV 1 D0
MOV 3 D1
MOV 0 D2
MOV 0 D3
MOV 0 D4
MOV 1 D5
MOV 1 D10
MOV 6 D11
MOV 0 D12
MOV 100 D13
MOV 0 D14
LD SM135
EU
INC D70
LD> D70 255
MOV 0 D70
LD SM0
MOV D70 D15
LD SM12
Modbus 1 D0 D100
LDI SM12
Modbus 1 D10 D200
// Q's D0 from the reply bytes: D300 = D103 * 256 + D104.
LD SM0
MUL D103 256 D300
ADD D301 D104 D302
