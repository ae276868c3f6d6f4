/* Batch mixer: fill, mix, drain (APLC-TCP), a small machine
   program written as SFC steps (STL, spec aplc.md §3.4).
   Inputs:  X0 start, X2 mixer running (motor feedback contact),
            X10 emergency stop (octal: input 8; held ON = everything stops).
   Outputs: Y0 inlet valve, Y1 mixer motor, Y2 drain valve, Y3 ready lamp.
   D100: tank level in mm (A/D). D0: batches done.
   S0 ready → (X0, tank empty) S20 fill to 1000 mm → S21 mix 5 s of running
   mixer (T0 counts only while X2 is ON) → S22 drain to 20 mm → S0. */
VAR_GLOBAL
    启动    X0      // start button
    运转    X2      // mixer running feedback
    急停    X10     // emergency stop (input 8)
    进料阀  Y0      // inlet valve
    搅拌机  Y1      // mixer motor
    排料阀  Y2      // drain valve
    液位    D100    // level, mm
END_VAR

POU MAIN
// Ladder block: power-on starts in the ready step.
LD      SM1
SET     S0

// Ready: a start with an empty tank begins a batch.
STL     S0
OUT     Y3
LD      启动
ANI     急停
AND<=   液位 20
SET     S20

// Fill to 1000 mm.
STL     S20
LDI     急停
OUT     进料阀
LD>=    液位 1000
SET     S21

// Mix: 5 s (T0, 100 ms base) of running mixer.
STL     S21
LDI     急停
OUT     搅拌机
LD      运转
ANI     急停
TON     T0 50
LD      T0
SET     S22

// Drain to 20 mm, count the batch.
STL     S22
LDI     急停
OUT     排料阀
LD<=    液位 20
INC     D0
LD<=    液位 20
SET     S0
RET
