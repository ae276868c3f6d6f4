/* The APLC manual's PID setup (the example of §6.11.1), verbatim with its
   comments. The first scan (SM1) sets SV D500 = 1000
   and the parameter block D510-D529: Ts 500 ms, mode 7 (reverse action,
   input- and output-change alarms), filter α 70 %, Kp 100 %, TI 2.5 s,
   KD 0, TD 630 ms, the working area D517-D524 cleared, alarm limits 2000.
   With M0 ON each scan reads PV, runs PID and writes MV.
   FROM/TO address an analog module APLC-TCP does not have: they load, and
   with power flow transfer nothing and record run error 73 (softplc's choice);
   in softplc the plant model of pid_setup.toml writes PV into D501 and reads
   MV from D502 instead. */

// PID 初始化程序，如果控制操作数不变，可以只执行一次
LD      SM1           //初始化程序只需运行一次
MOV     1000    D500   //设定目标值
MOV     500     D510   //采样时间 (Ts) 范围为 1~32767 (ms) 但比运算周期
                        //短的时间数值无法执行
MOV     7       D511   //动作方向
MOV     70     D512   //输入滤波常数 (α) 范围 0~99[%]为 0 时没有输入滤波功能
MOV     100    D513   //比例增益 (Kp) 范围 1~32767[%]
MOV    25      D514      //积分时间 (TI) 范围 0~32767 (×100ms) , 为 0 时作为
                               //∞处理 (无积分)
MOV    0        D515      //微分增益 (KD) 范围 0~100[%], 为 0 时无微分增益
MOV    63      D516      //微分时间 (TD) 范围 0~32767 (×10ms) , 为 0 时无微分
                               //处理
FMOV    0        D517      8  //清除 PID 运算中间数据存储区
MOV    2000     D525      //输入变化量 (增侧) 报警设定值 0~32767
MOV    2000     D526      //输入变化量 (减侧) 报警设定值 0~32767
MOV    2000     D527      //输出变化量 (增侧) 报警设定值 0~32767
MOV    2000     D528      //输出变化量 (减侧) 报警设定值 0~32767
//PID 指令执行运算
LD      M0                //用户控制 PID 运算程序
FROM    0    5    D501      1  //当前测量值读入 (用户可根据实际情况引入测量值)
PID      D500 D501 D510 D502  //PID 指令: PID S1 S2 S3 D
TO      0    8    D502      1  //PID 运算结果反馈到被控系统 (用户可根据实际情况
                               //处理 PID 运算结果)
