within Bicycle.Linear;
partial model PartialFrontBody "Body of the front assembly (front frame, front wheel): turns about the steer axis"
  extends Bicycle.Linear.PartialBody(
    final M11 = Jxx,
    final M12 = I_lx + mu*Jxz,
    final M22 = I_ll + 2*mu*I_lz + mu^2*Jzz,
    final K0_11 = mz,
    final K0_12 = -SA,
    final K0_22 = -SA*sin(lam),
    final K2_12 = (S - mz)*cos(lam)/w,
    final K2_22 = (SA + S*sin(lam))*cos(lam)/w,
    final C1_12 = mu*S + S*cos(lam) + Jxz*cos(lam)/w - mu*mz,
    final C1_21 = -(mu*S + S*cos(lam)),
    final C1_22 = I_lz*cos(lam)/w + mu*(SA + Jzz*cos(lam)/w));
  final parameter Bicycle.Units.Position u = (x - w - c)*cos(lam) - z*sin(lam) "Distance u of the centre of mass from the steer axis (A12; positive in front)";
  final parameter Bicycle.Units.MomentOfInertia I_ll = m*u^2 + Ixx*sin(lam)^2 + 2*Ixz*sin(lam)*cos(lam) + Izz*cos(lam)^2 "Inertia about the steer axis (part of IAll, A13)";
  final parameter Bicycle.Units.MomentOfInertia I_lx = -m*u*z + Ixx*sin(lam) + Ixz*cos(lam) "Inertia product of the steer axis and the x axis through the rear contact point (part of IAlx, A14)";
  final parameter Bicycle.Units.MomentOfInertia I_lz = m*u*x + Ixz*sin(lam) + Izz*cos(lam) "Inertia product of the steer axis and the z axis through the rear contact point (part of IAlz, A15)";
  final parameter Bicycle.Units.FirstMomentOfMass SA = m*u + mu*mx "Part of the static moment SA = mA uA + mu mT xT of the steer axis (A19)";
  annotation(Documentation(info = "<html>
<p>A body of the front assembly A = H + F. The steer axis has the unit vector (sin(lam), 0, cos(lam))
and passes through the point (w + c, 0, 0); u is the distance of the body's centre of mass from it.
The body's parts of the front assembly's moments (Meijaard 2007, A12-A15) are its static moment
m u about the steer axis, its inertia about the steer axis and its inertia products of the steer
axis with the x and z axes through the rear contact point:</p>
<pre>  I_ll = m u^2 + Ixx sin(lam)^2 + 2 Ixz sin(lam) cos(lam) + Izz cos(lam)^2
  I_lx = -m u z + Ixx sin(lam) + Ixz cos(lam)
  I_lz =  m u x + Ixz sin(lam) + Izz cos(lam)</pre>
<p>Summed over the front assembly they are Meijaard's mA uA, IAll, IAlx and IAlz (the
parallel-axis terms of A9-A11 cancel in the sums). A wheel of the front assembly adds its
gyrostatic coefficient S both to ST (A18) and as SF to the steer terms of C1 and K2 (A22-A25).
The parts of eq (24) are Meijaard's A20-A26 with the body's own moments.</p>
</html>"));
end PartialFrontBody;
