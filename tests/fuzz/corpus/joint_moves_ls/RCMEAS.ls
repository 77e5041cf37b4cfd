/PROG  RCMEAS
/ATTR
OWNER		= MNEDITOR;
COMMENT		= "robcal measure";
LINE_COUNT	= 27;
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
   1:  UFRAME_NUM=0 ;
   2:  UTOOL_NUM=1 ;
   3:  ! C1 ;
   4:J P[1] 10% FINE ;
   5:J P[2] 10% FINE ;
   6:  WAIT 1.00(sec) ;
   7:  WAIT DI[1]=ON ;
   8:  ! C2 ;
   9:J P[3] 10% FINE ;
  10:J P[4] 10% FINE ;
  11:  WAIT 1.00(sec) ;
  12:  WAIT DI[1]=ON ;
  13:  ! C3 ;
  14:J P[5] 10% FINE ;
  15:J P[6] 10% FINE ;
  16:  WAIT 1.00(sec) ;
  17:  WAIT DI[1]=ON ;
  18:  ! C4 ;
  19:J P[7] 10% FINE ;
  20:J P[8] 10% FINE ;
  21:  WAIT 1.00(sec) ;
  22:  WAIT DI[1]=ON ;
  23:  ! C5 ;
  24:J P[9] 10% FINE ;
  25:J P[10] 10% FINE ;
  26:  WAIT 1.00(sec) ;
  27:  WAIT DI[1]=ON ;
/POS
P[1]{
   GP1:
	UF : 0, UT : 1,
	J1= -68.719643 deg,	J2= 102.929103 deg,	J3= 61.451107 deg,
	J4= 77.246115 deg,	J5= 74.571688 deg,	J6= -50.440886 deg
};
P[2]{
   GP1:
	UF : 0, UT : 1,
	J1= -63.719643 deg,	J2= 107.929103 deg,	J3= 66.451107 deg,
	J4= 82.246115 deg,	J5= 79.571688 deg,	J6= -45.440886 deg
};
P[3]{
   GP1:
	UF : 0, UT : 1,
	J1= -40.026268 deg,	J2= -4.401993 deg,	J3= -82.206778 deg,
	J4= 64.529610 deg,	J5= 44.247444 deg,	J6= -47.060831 deg
};
P[4]{
   GP1:
	UF : 0, UT : 1,
	J1= -35.026268 deg,	J2= 0.598007 deg,	J3= -77.206778 deg,
	J4= 69.529610 deg,	J5= 49.247444 deg,	J6= -42.060831 deg
};
P[5]{
   GP1:
	UF : 0, UT : 1,
	J1= 80.839212 deg,	J2= 45.123563 deg,	J3= 55.497505 deg,
	J4= -86.760270 deg,	J5= 66.769648 deg,	J6= -31.608210 deg
};
P[6]{
   GP1:
	UF : 0, UT : 1,
	J1= 85.839212 deg,	J2= 50.123563 deg,	J3= 60.497505 deg,
	J4= -81.760270 deg,	J5= 71.769648 deg,	J6= -26.608210 deg
};
P[7]{
   GP1:
	UF : 0, UT : 1,
	J1= -26.945799 deg,	J2= 24.417800 deg,	J3= 61.201417 deg,
	J4= 30.153848 deg,	J5= -90.018035 deg,	J6= 91.682150 deg
};
P[8]{
   GP1:
	UF : 0, UT : 1,
	J1= -21.945799 deg,	J2= 29.417800 deg,	J3= 66.201417 deg,
	J4= 35.153848 deg,	J5= -85.018035 deg,	J6= 96.682150 deg
};
P[9]{
   GP1:
	UF : 0, UT : 1,
	J1= 29.137975 deg,	J2= 92.511547 deg,	J3= -63.514106 deg,
	J4= 51.254304 deg,	J5= -41.590867 deg,	J6= 98.405093 deg
};
P[10]{
   GP1:
	UF : 0, UT : 1,
	J1= 34.137975 deg,	J2= 97.511547 deg,	J3= -58.514106 deg,
	J4= 56.254304 deg,	J5= -36.590867 deg,	J6= 103.405093 deg
};
/END
