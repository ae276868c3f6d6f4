/* SFC: the structures of the APLC manual's chapter 7 in one flow, with the
   chapter's step, relay and timer numbers (the manual gives them as
   figures; this is their IL, a merge written as a run of STLs):
   - ladder block starting the flow at power-on: LD SM1 / SET S0;
   - initial step S0 (S0-S19), simple sequence to S20;
   - S20 times T2 before anything follows it;
   - selective branch: M20 → S27, M21 → S28, the user keeps them exclusive,
     and the selective merge into S29 on T12 / T13;
   - parallel branch: M30 activates S30 and S31 together, the
     parallel merge into S32 on M31 ends both;
   - a jump (OUT S0) back to the initial step: a loop;
   - RET ends the SFC section.
   Outputs: Y0 ready (S0), Y1 S20, Y2 S27, Y3 S28, Y4 S29, Y5 S30, Y6 S31,
   Y7 S32. X0 starts a cycle, X1 ends it. */

// Ladder block: power-on starts the flow.
LD      SM1
SET     S0

// Initial step: ready; X0 starts.
STL     S0
OUT     Y0
LD      X0
SET     S20

// S20: 2 s on T2 (100 ms base), then the selective branch.
STL     S20
OUT     Y1
TON     T2 20
LD      T2
AND     M20
SET     S27
LD      T2
AND     M21
SET     S28

// Branch 1: 1 s on T12.
STL     S27
OUT     Y2
TON     T12 10
LD      T12
SET     S29

// Branch 2: 2 s on T13.
STL     S28
OUT     Y3
TON     T13 20
LD      T13
SET     S29

// Selective merge: S29; M30 starts both parallel branches.
STL     S29
OUT     Y4
LD      M30
SET     S30
SET     S31

STL     S30
OUT     Y5

STL     S31
OUT     Y6

// Parallel merge: S30 and S31 active and M31.
STL     S30
STL     S31
LD      M31
SET     S32

// Last step: X1 jumps back to the initial step.
STL     S32
OUT     Y7
LD      X1
OUT     S0
RET
