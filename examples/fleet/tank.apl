// Tank PLC (APLC-TCP): an on/off level loop with 20 mm of hysteresis. D0 is
// the level in mm (the level transmitter), D1 the setpoint in mm, written by
// the line master over PORT1 (a Modbus slave: holding register 1). The
// inlet pump Y0 starts below D1 - 20 and stops above D1 + 20.
LD SM0
SUB D1 20 D10
ADD D1 20 D11
LD< D0 D10
SET Y0
LD> D0 D11
RST Y0
