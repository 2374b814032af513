MODULE Module1
    PERS tooldata Tip:=[TRUE,[[0,0,150],[1,0,0,0]],[1.5,[0,0,60],[1,0,0,0],0,0,0]];
    TASK PERS wobjdata Workobject_plano:=[FALSE,TRUE,"",[[800,-200,0],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
    TASK PERS wobjdata Workobject_inclinado:=[FALSE,TRUE,"",[[700,300,350],[0.965925826,0,0.258819045,0]],[[0,0,0],[1,0,0,0]]];
    TASK PERS wobjdata Workobject_mesa:=[FALSE,TRUE,"",[[800,-200,0],[1,0,0,0]],[[400,0,0],[0.707106781,0,0,0.707106781]]];
    CONST robtarget Target_home:=[[520.5,-0.2,640.8],[0.258819045,0,-0.965925826,0],[-1,-2,1,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_10:=[[0,0,0],[0,1,0,0],[0,-2,1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_20:=[[120,0,0],[0,1,0,0],[0,-2,1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_30:=[[180,60,0],[0,1,0,0],[0,-2,1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_40:=[[120,120,0],[0,1,0,0],[0,-2,1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_50:=[[0,120,0],[0,1,0,0],[-1,-2,1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_60:=[[0,0,15],[0,1,0,0],[-1,-1,0,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_70:=[[120,0,15],[0,1,0,0],[-1,-1,0,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_80:=[[180,60,15],[0,1,0,0],[-1,-1,0,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_90:=[[120,120,15],[0,1,0,0],[-1,-1,0,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_100:=[[0,120,15],[0,1,0,0],[-1,-1,0,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_110:=[[0,120,70],[0,1,0,0],[-1,-1,0,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_120:=[[0,0,70],[0,1,0,0],[-1,-1,0,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_130:=[[100,0,0],[0,1,0,0],[-1,-1,0,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_140:=[[100,60,0],[0,1,0,0],[-1,-1,0,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_150:=[[0,60,0],[0,1,0,0],[-1,-1,0,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
!***********************************************************
    !
    ! Module:  Module1
    !
    ! Description:
    !   Two layers of a D-shaped outline on the flat table or on the tilted plate, chosen by
    !   the operator's inputs; a rectangle on the table's second work object.
    !
    !***********************************************************

    !***********************************************************
    !
    ! Procedure main
    !
    !   This is the entry point of your program
    !
    !***********************************************************
    PROC main()
        IF DI_01=1 AND DI_02=0 THEN
          path_plano;
        ELSEIF DI_01=0 AND DI_02=1 THEN
          path_inclinado;
        ENDIF
    ENDPROC
    PROC path_plano()
        MoveJ Target_home,v300,z50,Tip\WObj:=wobj0;
        MoveJ Target_110,v300,z10,Tip\WObj:=Workobject_plano;
        MoveJ Target_50,v300,z0,Tip\WObj:=Workobject_plano;
        MoveL Target_10,v100,z1,Tip\WObj:=Workobject_plano;
        MoveL Target_20,v100,z1,Tip\WObj:=Workobject_plano;
        MoveC Target_30,Target_40,v100,z1,Tip\WObj:=Workobject_plano;
        MoveL Target_50,v100,z1,Tip\WObj:=Workobject_plano;
        MoveL Target_100,v100,z1,Tip\WObj:=Workobject_plano;
        MoveL Target_60,v100,z1,Tip\WObj:=Workobject_plano;
        MoveL Target_70,v100,z1,Tip\WObj:=Workobject_plano;
        MoveC Target_80,Target_90,v100,z1,Tip\WObj:=Workobject_plano;
        MoveL Target_100,v100,z1,Tip\WObj:=Workobject_plano;
        MoveJ Target_110,v300,z10,Tip\WObj:=Workobject_plano;
        rectangulo_mesa;
        MoveJ Target_home,v300,z50,Tip\WObj:=wobj0;
    ENDPROC
    PROC rectangulo_mesa()
        MoveJ Target_120,v300,z10,Tip\WObj:=Workobject_mesa;
        MoveJ Target_10,v300,fine,Tip\WObj:=Workobject_mesa;
        MoveL Target_130,v100,z1,Tip\WObj:=Workobject_mesa;
        MoveL Target_140,v100,z1,Tip\WObj:=Workobject_mesa;
        MoveL Target_150,v100,z1,Tip\WObj:=Workobject_mesa;
        MoveL Target_10,v100,fine,Tip\WObj:=Workobject_mesa;
        MoveJ Target_120,v300,z10,Tip\WObj:=Workobject_mesa;
    ENDPROC
    PROC path_inclinado()
        MoveJ Target_home,v300,z50,Tip\WObj:=wobj0;
        MoveJ Target_110,v300,z10,Tip\WObj:=Workobject_inclinado;
        MoveJ Target_50,v300,z0,Tip\WObj:=Workobject_inclinado;
        MoveL Target_10,v100,z1,Tip\WObj:=Workobject_inclinado;
        MoveL Target_20,v100,z1,Tip\WObj:=Workobject_inclinado;
        MoveC Target_30,Target_40,v100,z1,Tip\WObj:=Workobject_inclinado;
        MoveL Target_50,v100,z1,Tip\WObj:=Workobject_inclinado;
        MoveL Target_100,v100,z1,Tip\WObj:=Workobject_inclinado;
        MoveL Target_60,v100,z1,Tip\WObj:=Workobject_inclinado;
        MoveL Target_70,v100,z1,Tip\WObj:=Workobject_inclinado;
        MoveC Target_80,Target_90,v100,z1,Tip\WObj:=Workobject_inclinado;
        MoveL Target_100,v100,z1,Tip\WObj:=Workobject_inclinado;
        MoveJ Target_110,v300,z10,Tip\WObj:=Workobject_inclinado;
        MoveJ Target_home,v300,z50,Tip\WObj:=wobj0;
    ENDPROC
ENDMODULE
