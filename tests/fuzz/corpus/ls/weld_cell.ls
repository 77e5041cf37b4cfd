/PROG  WELD_CELL
/ATTR
OWNER		= MNEDITOR;
COMMENT		= "robcal test";
PROG_SIZE	= 1320;
CREATE		= DATE 26-11-24  TIME 10:00:00;
MODIFIED	= DATE 26-11-24  TIME 10:00:00;
FILE_NAME	= ;
VERSION		= 0;
LINE_COUNT	= 8;
MEMORY_SIZE	= 1640;
PROTECT		= READ_WRITE;
TCD:  STACK_SIZE	= 0,
      TASK_PRIORITY	= 50,
      TIME_SLICE	= 0,
      BUSY_LAMP_OFF	= 0,
      ABORT_REQUEST	= 0,
      PAUSE_REQUEST	= 0;
DEFAULT_GROUP	= 1,*,*,*,*;
CONTROL_CODE	= 00000000 00000000;
/MN
   1:  UFRAME_NUM=1 ;
   2:  UTOOL_NUM=2 ;
   3:J P[1] 20% FINE    ;
   4:  ! approach X = 1.0 mm in a comment ;
   5:L P[2] 100mm/sec CNT50    ;
   6:L P[3] 50mm/sec FINE    ;
   7:J P[4:home] 10% FINE    ;
   8:  WAIT   0.50(sec) ;
/POS
P[1]{
   GP1:
	UF : 1, UT : 2,		CONFIG : 'N U T, 0, 0, 0',
	X =   450.000  mm,	Y =  -120.500  mm,	Z =   380.250  mm,
	W =   180.000 deg,	P =   -10.000 deg,	R =    45.000 deg
};
P[2]{
   GP1:
	UF : 1, UT : 2,		CONFIG : 'N U T, 0, 0, 0',
	X =   470.125  mm,	Y =   -80.000  mm,	Z =   300.000  mm,
	W =   175.500 deg,	P =     5.250 deg,	R =    30.000 deg
   GP2:
	UF : 1, UT : 2,
	J1=     0.000  mm
};
P[3]{
   GP1:
	UF : 0, UT : 2,		CONFIG : 'N U T, 0, 0, 0',
	X = 500.0 mm, Y = 0.0 mm, Z = 350.0 mm,
	W = -170.0 deg, P = 0.0 deg, R = 90.0 deg
};
P[4:"home"]{
   GP1:
	UF : 0, UT : 2,
	J1=     0.000 deg,	J2=   -10.000 deg,	J3=    20.000 deg,
	J4=     0.000 deg,	J5=   -60.000 deg,	J6=     0.000 deg
};
/END
