// The browser test's APLC program (tests/python/test_web_monitor.py).
VAR_GLOBAL
    急停    X10     // emergency stop: octal X10 is input 8
    电机    Y0      // motor
END_VAR
POU MAIN
// The motor runs while the emergency stop is not pressed, or by M0.
LDI     急停
AND     SM0
OR      M0
OUT     电机
// An SFC step started at power-on.
LD      SM1
SET     S0
STL     S0
LD      SM0
OUT     Y1
RET
