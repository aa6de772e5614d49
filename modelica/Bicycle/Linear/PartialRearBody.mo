within Bicycle.Linear;
partial model PartialRearBody "Body of the rear assembly (rear wheel, rear frame): does not turn about the steer axis"
  extends Bicycle.Linear.PartialBody(
    final M11 = Jxx,
    final M12 = mu*Jxz,
    final M22 = mu^2*Jzz,
    final K0_11 = mz,
    final K0_12 = -mu*mx,
    final K0_22 = -mu*mx*sin(lam),
    final K2_12 = (S - mz)*cos(lam)/w,
    final K2_22 = mu*mx*cos(lam)/w,
    final C1_12 = mu*S + Jxz*cos(lam)/w - mu*mz,
    final C1_21 = -mu*S,
    final C1_22 = mu*(mu*mx + Jzz*cos(lam)/w));
  annotation(Documentation(info = "<html>
<p>A body rigidly attached to the rear frame. It contributes to the whole bicycle's moments
(Meijaard 2007, A1-A6: mT xT, mT zT, ITxx, ITxz, ITzz), to the static moment SA = mA uA + mu mT xT
through mu m x (A19) and, as a wheel, to ST = SR + SF (A18), but not to the front assembly's moments
about the steer axis (A7-A15). Its parts of eq (24) are Meijaard's formulas A20-A26 with only its
own moments:</p>
<pre>  M   = [Jxx, mu Jxz; mu Jxz, mu^2 Jzz]
  K0  = [m z, -mu m x; -mu m x, -mu m x sin(lam)]
  K2  = [0, (S - m z) cos(lam)/w; 0, mu m x cos(lam)/w]
  C1  = [0, mu S + Jxz cos(lam)/w - mu m z; -mu S, mu (mu m x + Jzz cos(lam)/w)]</pre>
</html>"));
end PartialRearBody;
