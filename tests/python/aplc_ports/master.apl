// Polls station 3 (FC 03) at X0's rising edge: registers 0-1 into D100..;
// at X1's, registers 40-41 (past the slave's block: exception 02) into D200..
// Shared by test_aplc_ports.py (pymodbus over a pty) and master.toml.
LD SM1
MOV 3 D0
MOV 3 D1
MOV 0 D2
MOV 0 D3
MOV 0 D4
MOV 2 D5
MOV 3 D10
MOV 3 D11
MOV 0 D12
MOV 40 D13
MOV 0 D14
MOV 2 D15
LD X0
Modbus 1 D0 D100
LD X1
Modbus 1 D10 D200
