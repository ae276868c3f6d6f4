/* Conveyor with batch counter (APLC-TCP dialect).
   X0 start, X1 stop, X2 box sensor, X10 emergency stop (octal: input 8);
   Y0 conveyor motor, Y1 batch-complete lamp, Y2 running lamp (blinks 1 s). */
VAR_GLOBAL
    启动    X0      // start button
    停止    X1      // stop button
    光电    X2      // box sensor
    急停    X10     // emergency stop (octal X10 = input 8)
    电机    Y0      // conveyor motor
    完成    Y1      // batch complete
END_VAR

POU MAIN
VAR
    RUNOK  TEMP BOOL
END_VAR
// Run latch: start sets M0, stop or a full batch resets it.
LD      启动
ANI     急停
SET     M0
LD      停止
OR      急停
OR      C0
RST     M0

// Everything below stops while the emergency stop is pressed.
LDI     急停
MC      0
LD      M0
OUT     #RUNOK
LD      #RUNOK
OUT     电机
AND     SM12
OUT     Y2
MCR     0

// Count boxes on the sensor's rising edge; a batch is 10 boxes.
LD      光电
AND     电机
CTU     C0 10
LD      C0
OUT     完成
// The lamp stays 3 s (T1, 100 ms base), then the counter restarts.
LD      C0
TON     T1 30
LD      T1
RST     C0

// Throughput: boxes × 100 as a 32-bit value, high word in D10.
LD      SM0
MUL     C0 100 D10
DMOV    D10 D20
LDD>=   D20 500
OUT     M10
