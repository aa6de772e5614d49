within Bicycle.Bicycles;
model WhippleLinear "Linearized Whipple bicycle, eq (24): M q'' + v C1 q' + (g K0 + v^2 K2) q = [T_phi, T_delta] (Meijaard et al. 2007)"
  extends Bicycle.Icons.Bike;
  extends Bicycle.Bicycles.PartialWhippleParameters(
    w = Data.w, c = Data.c, lam = Data.lam, g = Data.g,
    rR = Data.rR, mR = Data.mR, IRxx = Data.IRxx, IRyy = Data.IRyy,
    xB = Data.xB, zB = Data.zB, mB = Data.mB,
    IBxx = Data.IBxx, IBxz = Data.IBxz, IByy = Data.IByy, IBzz = Data.IBzz,
    xH = Data.xH, zH = Data.zH, mH = Data.mH,
    IHxx = Data.IHxx, IHxz = Data.IHxz, IHyy = Data.IHyy, IHzz = Data.IHzz,
    rF = Data.rF, mF = Data.mF, IFxx = Data.IFxx, IFyy = Data.IFyy);
  replaceable package Data = Bicycle.Records.Benchmark constrainedby Bicycle.Records.PartialWhipple "Parameter set giving the defaults (Meijaard's Table 1 symbols)";
  // Operating point and initial state (the 26 parameters of Meijaard's Table 1 are inherited)
  parameter Bicycle.Units.Velocity v = 5 "Forward speed v of the rear contact point (negative: riding backwards, i.e. a rear-steered bicycle)";
  parameter Bicycle.Units.Angle phi0 = 0 "Initial roll angle";
  parameter Bicycle.Units.Angle delta0 = 0 "Initial steer angle";
  parameter Bicycle.Units.AngularVelocity phi_dot0 = 0 "Initial roll rate";
  parameter Bicycle.Units.AngularVelocity delta_dot0 = 0 "Initial steer rate";

  Bicycle.Linear.RearWheel rearWheel(w = w, c = c, lam = lam, g = g, v = v, r = rR, m = mR, Ixx = IRxx, Iyy = IRyy) "Rear wheel R"
    annotation(Placement(transformation(extent = {{-150, -20}, {-90, 40}})));
  Bicycle.Linear.LinearizedRearFrame rearFrame(w = w, c = c, lam = lam, g = g, v = v, m = mB, x = xB, z = zB, Ixx = IBxx, Ixz = IBxz, Iyy = IByy, Izz = IBzz) "Rear frame B with rider"
    annotation(Placement(transformation(extent = {{-70, 50}, {-30, 90}})));
  Bicycle.Linear.LinearizedFrontFrame frontFrame(w = w, c = c, lam = lam, g = g, v = v, m = mH, x = xH, z = zH, Ixx = IHxx, Ixz = IHxz, Iyy = IHyy, Izz = IHzz) "Front frame H (fork and handlebar)"
    annotation(Placement(transformation(extent = {{30, 50}, {70, 90}})));
  Bicycle.Linear.FrontWheel frontWheel(w = w, c = c, lam = lam, g = g, v = v, r = rF, m = mF, Ixx = IFxx, Iyy = IFyy) "Front wheel F"
    annotation(Placement(transformation(extent = {{90, -20}, {150, 40}})));
  Bicycle.Linear.Torques torques "Roll and steer torques"
    annotation(Placement(transformation(extent = {{-30, 110}, {30, 170}})));
  Bicycle.Linear.Coordinates coordinates "Roll and steer coordinates: give the states to the components, return the accelerations of eq (24)"
    annotation(Placement(transformation(extent = {{40, -120}, {-40, -40}})));

  // The matrices of eq (24), the sums of the bodies' parts (for inspection; the dynamics use the connection set)
  final parameter Bicycle.Units.MomentOfInertia M11 = rearWheel.M11 + rearFrame.M11 + frontFrame.M11 + frontWheel.M11 "Mass matrix M, element (phi, phi)";
  final parameter Bicycle.Units.MomentOfInertia M12 = rearWheel.M12 + rearFrame.M12 + frontFrame.M12 + frontWheel.M12 "Mass matrix M, element (phi, delta)";
  final parameter Bicycle.Units.MomentOfInertia M21 = M12 "Mass matrix M, element (delta, phi) = M12";
  final parameter Bicycle.Units.MomentOfInertia M22 = rearWheel.M22 + rearFrame.M22 + frontFrame.M22 + frontWheel.M22 "Mass matrix M, element (delta, delta)";
  final parameter Bicycle.Units.FirstMomentOfMass K0_11 = rearWheel.K0_11 + rearFrame.K0_11 + frontFrame.K0_11 + frontWheel.K0_11 "Gravity stiffness K0, element (phi, phi)";
  final parameter Bicycle.Units.FirstMomentOfMass K0_12 = rearWheel.K0_12 + rearFrame.K0_12 + frontFrame.K0_12 + frontWheel.K0_12 "Gravity stiffness K0, element (phi, delta)";
  final parameter Bicycle.Units.FirstMomentOfMass K0_21 = K0_12 "Gravity stiffness K0, element (delta, phi) = K0_12";
  final parameter Bicycle.Units.FirstMomentOfMass K0_22 = rearWheel.K0_22 + rearFrame.K0_22 + frontFrame.K0_22 + frontWheel.K0_22 "Gravity stiffness K0, element (delta, delta)";
  final parameter Bicycle.Units.MassCoefficient K2_12 = rearWheel.K2_12 + rearFrame.K2_12 + frontFrame.K2_12 + frontWheel.K2_12 "Velocity-squared stiffness K2, element (phi, delta); K2_11 = K2_21 = 0";
  final parameter Bicycle.Units.MassCoefficient K2_22 = rearWheel.K2_22 + rearFrame.K2_22 + frontFrame.K2_22 + frontWheel.K2_22 "Velocity-squared stiffness K2, element (delta, delta)";
  final parameter Bicycle.Units.FirstMomentOfMass C1_12 = rearWheel.C1_12 + rearFrame.C1_12 + frontFrame.C1_12 + frontWheel.C1_12 "Velocity-proportional matrix C1, element (phi, delta); C1_11 = 0";
  final parameter Bicycle.Units.FirstMomentOfMass C1_21 = rearWheel.C1_21 + rearFrame.C1_21 + frontFrame.C1_21 + frontWheel.C1_21 "Velocity-proportional matrix C1, element (delta, phi)";
  final parameter Bicycle.Units.FirstMomentOfMass C1_22 = rearWheel.C1_22 + rearFrame.C1_22 + frontFrame.C1_22 + frontWheel.C1_22 "Velocity-proportional matrix C1, element (delta, delta)";

  Bicycle.Interfaces.RealInput T_phi(final quantity = "Torque", final unit = "N.m") "Roll torque T_phi on the rear frame, positive tending to lean right"
    annotation(Placement(transformation(extent = {{-220, 142}, {-200, 162}}), iconTransformation(extent = {{-140, -60}, {-100, -20}})));
  Bicycle.Interfaces.RealInput T_delta(final quantity = "Torque", final unit = "N.m") "Steer torque T_delta between rear frame and front frame, positive tending to steer right"
    annotation(Placement(transformation(extent = {{-220, 118}, {-200, 138}}), iconTransformation(extent = {{-140, 20}, {-100, 60}})));
  Bicycle.Interfaces.RealOutput phi(final quantity = "Angle", final unit = "rad", displayUnit = "deg", start = phi0, fixed = true) "Roll angle phi of the rear frame, positive leaning right"
    annotation(Placement(transformation(extent = {{202, -64}, {218, -48}}), iconTransformation(extent = {{100, 65}, {120, 85}})));
  Bicycle.Interfaces.RealOutput delta(final quantity = "Angle", final unit = "rad", displayUnit = "deg", start = delta0, fixed = true) "Steer angle delta, positive steering right"
    annotation(Placement(transformation(extent = {{202, -80}, {218, -64}}), iconTransformation(extent = {{100, 35}, {120, 55}})));
  Bicycle.Interfaces.RealOutput phi_dot(final quantity = "AngularVelocity", final unit = "rad/s", start = phi_dot0, fixed = true) "Roll rate der(phi)"
    annotation(Placement(transformation(extent = {{202, -96}, {218, -80}}), iconTransformation(extent = {{100, 5}, {120, 25}})));
  Bicycle.Interfaces.RealOutput delta_dot(final quantity = "AngularVelocity", final unit = "rad/s", start = delta_dot0, fixed = true) "Steer rate der(delta)"
    annotation(Placement(transformation(extent = {{202, -112}, {218, -96}}), iconTransformation(extent = {{100, -25}, {120, -5}})));
  Bicycle.Interfaces.RealOutput psi(final quantity = "Angle", final unit = "rad", displayUnit = "deg", start = 0, fixed = true) "Yaw (heading) angle psi of the rear frame, positive turning right (about the downward z axis)"
    annotation(Placement(transformation(extent = {{202, 122}, {218, 138}}), iconTransformation(extent = {{100, -55}, {120, -35}})));
  Bicycle.Interfaces.RealOutput y(final quantity = "Length", final unit = "m", start = 0, fixed = true) "Lateral position y of the rear contact point, positive to the right of the initial path"
    annotation(Placement(transformation(extent = {{202, 102}, {218, 118}}), iconTransformation(extent = {{100, -85}, {120, -65}})));
equation
  connect(coordinates.frame, rearWheel.frame) annotation(Line(points = {{0, -40}, {0, -30}, {-120, -30}, {-120, -20}}, color = {0, 128, 128}, thickness = 0.5));
  connect(coordinates.frame, rearFrame.frame) annotation(Line(points = {{0, -40}, {0, -30}, {-50, -30}, {-50, 50}}, color = {0, 128, 128}, thickness = 0.5));
  connect(coordinates.frame, frontFrame.frame) annotation(Line(points = {{0, -40}, {0, -30}, {50, -30}, {50, 50}}, color = {0, 128, 128}, thickness = 0.5));
  connect(coordinates.frame, frontWheel.frame) annotation(Line(points = {{0, -40}, {0, -30}, {120, -30}, {120, -20}}, color = {0, 128, 128}, thickness = 0.5));
  connect(coordinates.frame, torques.frame) annotation(Line(points = {{0, -40}, {0, 110}}, color = {0, 128, 128}, thickness = 0.5));
  connect(T_phi, torques.T_phi) annotation(Line(points = {{-210, 152}, {-36, 152}}, color = {0, 0, 127}));
  connect(T_delta, torques.T_delta) annotation(Line(points = {{-210, 128}, {-36, 128}}, color = {0, 0, 127}));
  // The states live here (they keep their names in the FMU); the coordinates give their accelerations.
  connect(phi, coordinates.phi) annotation(Line(points = {{210, -56}, {48, -56}}, color = {0, 0, 127}));
  connect(delta, coordinates.delta) annotation(Line(points = {{210, -72}, {48, -72}}, color = {0, 0, 127}));
  connect(phi_dot, coordinates.phi_dot) annotation(Line(points = {{210, -88}, {48, -88}}, color = {0, 0, 127}));
  connect(delta_dot, coordinates.delta_dot) annotation(Line(points = {{210, -104}, {48, -104}}, color = {0, 0, 127}));
  der(phi) = phi_dot;
  der(delta) = delta_dot;
  der(phi_dot) = coordinates.phi_ddot;
  der(delta_dot) = coordinates.delta_ddot;
  // Heading and path of the rear contact point, linearized about straight running
  der(psi) = (v*delta + c*delta_dot)*cos(lam)/w;
  der(y) = v*psi;
  annotation(
    Icon(graphics = {
      Text(extent = {{20, 96}, {100, 56}}, textString = "(24)", textColor = {64, 64, 64})}),
    Diagram(coordinateSystem(extent = {{-220, -130}, {220, 190}})),
    experiment(StartTime = 0, StopTime = 5, Tolerance = 1e-8, Interval = 0.01),
    __Cosim(export = true),
    Documentation(info = "<html>
<p>The linearized Whipple bicycle of J. P. Meijaard, J. M. Papadopoulos, A. Ruina and A. L. Schwab,
<em>Linearized dynamics equations for the balance and steer of a bicycle: a benchmark and review</em>,
Proc. R. Soc. A 463 (2007) 1955-1982, which is eq (24) of Astrom, Klein and Lennartsson (2005):</p>
<pre>  M q'' + v C1 q' + (g K0 + v^2 K2) q = [T_phi; T_delta],   q = [phi; delta]</pre>
<p>The model is an assembly of the components of <a href=\"modelica://Bicycle.Linear\">Bicycle.Linear</a>:
four bodies (rear wheel, rear frame, front frame, front wheel), each carrying its own mass
properties and contributing its part of M, C1, K0 and K2 (Meijaard's Appendix A applied to the
body's own moments), the applied torques, and the coordinates, which hold no force of their own:
each component delivers the generalized force that balances its part of eq (24), inertia terms
M_i q'' included, and the flow sum of the connection set is eq (24), which the accelerations
shared by the set satisfy. The calculated
parameters M11 ... K2_22 are the same sums, for inspection. The top-level parameters carry the
names of Meijaard's Table 1 (declared in <a href=\"modelica://Bicycle.Bicycles.PartialWhippleParameters\">PartialWhippleParameters</a>;
the rear frame B includes the rider, and the inertias IByy and IHyy do not enter the linear
model); their defaults come from the replaceable package <code>Data</code>
(the benchmark bicycle, <a href=\"modelica://Bicycle.Records.Benchmark\">Bicycle.Records.Benchmark</a>,
generated from <code>cosim/params/benchmark.toml</code>), for which M, C1, K0, K2 equal the
published 14-digit values and the bicycle is self-stable for 4.292 m/s &lt; v &lt; 6.024 m/s.
Another data set is one redeclaration:
<code>extends WhippleLinear(redeclare package Data = Bicycle.Records.Astrom2005)</code>.
Structural zeros C1_11 = K2_11 = K2_21 = 0 are not declared.</p>
<p><b>Sign conventions are those of Meijaard (2007)</b>, not the ISO 8855 conventions of the
rest of this library: axes x forward, y right, z down; roll phi positive leaning right, steer
delta and steer torque T_delta positive steering right (Astrom et al. 2005 count the steer
angle positive to the left: their matrices are S M S etc. with S = diag(1, -1)), yaw psi
positive turning right, lateral position y of the rear contact point positive to the right.
The heading and path kinematics, linearized about straight running at speed v, are
(Meijaard 2007, section 3):</p>
<pre>  der(psi) = (v delta + c der(delta)) cos(lam)/w,   der(y) = v psi</pre>
<p>psi and y do not feed back into the dynamics: the continuous states are, in this order,
phi, delta, phi_dot, delta_dot, psi, y, and the upper-left 4x4 block of the state matrix is the
Whipple model's (its eigenvalues are the bicycle's; psi and y add two eigenvalues at zero).
A negative speed v is riding backwards, i.e. a rear-steered bicycle.</p>
</html>"));
end WhippleLinear;
