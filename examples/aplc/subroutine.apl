/* The APLC manual's subroutine example (Example 5). SBR_1's variable table
   IN1/IN2/OUT1 on V0/V1/V2 and its body `ADD #IN1 #IN2 #OUT1`; MAIN calls
   it with `CALL SBR_1 3 2 D0` under M0. With M0 ON, D0 = 3 + 2 = 5. The
   manual shows the POU names and the table only as editor screens; this is
   their text form in softplc's .apl files (POU headers, VAR tables). */
POU SBR_1
VAR
    IN1   IN   INT      // V0
    IN2   IN   INT      // V1
    OUT1  OUT  INT      // V2
END_VAR
LD SM0
ADD #IN1 #IN2 #OUT1

POU MAIN
LD M0
CALL SBR_1 3 2 D0
