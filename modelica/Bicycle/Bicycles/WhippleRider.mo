within Bicycle.Bicycles;
model WhippleRider "Nonlinear Whipple bicycle with a leaning rider: the upper body on a hip hinge of the rear frame (Meijaard et al. 2007 bicycle, Astrom et al. 2005 rider lean)"
  extends Bicycle.Icons.BikeRider;
  extends Bicycle.Bicycles.PartialWhippleParameters(
    w = Data.w, c = Data.c, lam = Data.lam, g = Data.g,
    rR = Data.rR, mR = Data.mR, IRxx = Data.IRxx, IRyy = Data.IRyy,
    xB = Data.xB, zB = Data.zB, mB = Data.mB,
    IBxx = Data.IBxx, IBxz = Data.IBxz, IByy = Data.IByy, IBzz = Data.IBzz,
    xH = Data.xH, zH = Data.zH, mH = Data.mH,
    IHxx = Data.IHxx, IHxz = Data.IHxz, IHyy = Data.IHyy, IHzz = Data.IHzz,
    rF = Data.rF, mF = Data.mF, IFxx = Data.IFxx, IFyy = Data.IFyy);
  replaceable package Data = Bicycle.Records.BenchmarkRider constrainedby Bicycle.Records.PartialWhippleRider "Parameter set (the values of the parameters bound in the extends clause)";
  constant Integer n = 7 "Number of generalized speeds: 1 to 3 dependent (yaw, pitch, front wheel), 4 roll, 5 steer, 6 rear wheel, 7 lean";
  parameter Bicycle.Units.Length tR(min = 0) = 0 "Rear tyre crown radius tR (toroidal wheel; 0: knife edge)";
  parameter Bicycle.Units.Position x0 = 0 "Initial x coordinate of the rear contact point";
  parameter Bicycle.Units.Position y0 = 0 "Initial y coordinate of the rear contact point (right)";
  parameter Bicycle.Units.Angle psi0 = 0 "Initial yaw angle";
  parameter Bicycle.Units.Angle phi0 = 0 "Initial roll angle";
  parameter Bicycle.Units.Angle delta0 = 0 "Initial steer angle";
  parameter Bicycle.Units.Angle thetaR0 = 0 "Initial rear wheel angle";
  parameter Bicycle.Units.Angle thetaF0 = 0 "Initial front wheel angle";
  parameter Bicycle.Units.AngularVelocity u_phi0 = 0 "Initial roll rate";
  parameter Bicycle.Units.AngularVelocity u_delta0 = 0 "Initial steer rate";
  parameter Bicycle.Units.AngularVelocity u_R0 = -16.666666666666668 "Initial rear wheel rate (relative to the rear frame); forward speed v = -u_R0*rR when upright (default: 5 m/s for rR = 0.3 m)";
  parameter Bicycle.Units.Angle theta_guess = 0 "Starting value of the Newton iteration for the initial pitch";
  parameter Bicycle.Units.Angle beta0 = 0 "Initial lean angle of the upper body relative to the rear frame";
  parameter Bicycle.Units.AngularVelocity u_beta0 = 0 "Initial lean rate of the upper body";
  parameter Bicycle.Units.Length tF(min = 0) = 0 "Front tyre crown radius tF (toroidal wheel; 0: knife edge)";
  parameter Bicycle.Units.Mass mU(min = 0) = Data.mU "Upper body mass mU";
  parameter Bicycle.Units.Position xU = Data.xU "Hinge (hip) axis and upper body centre of mass: x coordinate xU (forward)";
  parameter Bicycle.Units.Length hU = Data.hU "Height hU of the hinge (hip) axis above the ground (upright bicycle)";
  parameter Bicycle.Units.Length lU = Data.lU "Height lU of the upper body centre of mass above the hinge axis";
  parameter Bicycle.Units.MomentOfInertia IUxx(min = 0) = Data.IUxx "Upper body inertia-tensor element IUxx about its centre of mass";
  parameter Bicycle.Units.MomentOfInertia IUxz = Data.IUxz "Upper body inertia-tensor element IUxz about its centre of mass";
  parameter Bicycle.Units.MomentOfInertia IUyy(min = 0) = Data.IUyy "Upper body inertia-tensor element IUyy about its centre of mass";
  parameter Bicycle.Units.MomentOfInertia IUzz(min = 0) = Data.IUzz "Upper body inertia-tensor element IUzz about its centre of mass";
  parameter Real kU(final quantity = "RotationalSpringConstant", final unit = "N.m/rad", min = 0) = Data.kU "Passive stiffness kU of the hip hinge (lean torque per lean angle)";
  parameter Real cU(final quantity = "RotationalDampingConstant", final unit = "N.m.s/rad", min = 0) = Data.cU "Passive damping cU of the hip hinge (lean torque per lean rate)";
  Bicycle.Interfaces.RealInput T_delta(final quantity = "Torque", final unit = "N.m") "Steer torque T_delta between rear frame and front frame, positive tending to steer right"
    annotation(Placement(transformation(origin = {10, 250}, extent = {{-10, -10}, {10, 10}}, rotation = -90), iconTransformation(extent = {{-140, 40}, {-100, 80}})));
  Bicycle.Interfaces.RealInput T_phi(final quantity = "Torque", final unit = "N.m") "Roll torque T_phi on the rear frame about the (horizontal) roll axis, positive tending to lean right (disturbance)"
    annotation(Placement(transformation(extent = {{-220, -100}, {-200, -80}}), iconTransformation(extent = {{-140, -80}, {-100, -40}})));
  Bicycle.Interfaces.RealInput T_beta(final quantity = "Torque", final unit = "N.m") "Lean torque T_beta of the rider between rear frame and upper body, positive tending to lean the upper body right"
    annotation(Placement(transformation(extent = {{-220, 132}, {-200, 152}}), iconTransformation(extent = {{-140, 0}, {-100, 40}})));
  output Bicycle.Units.Position x = ground.x "x coordinate (forward at yaw 0) of the rear contact point";
  output Bicycle.Units.Position y = ground.y "y coordinate (right at yaw 0) of the rear contact point: lateral position";
  output Bicycle.Units.Angle psi = ground.psi "Yaw angle psi of the rear frame, positive turning right";
  output Bicycle.Units.Angle phi = ground.phi "Roll angle phi of the rear frame, positive leaning right";
  output Bicycle.Units.Angle theta = ground.theta "Pitch angle theta of the rear frame, positive nose up (0: upright, zero steer)";
  output Bicycle.Units.Angle delta = steer.angle "Steer angle delta, positive steering right";
  output Bicycle.Units.Angle thetaR = rearWheel.angle "Rear wheel angle relative to the rear frame";
  output Bicycle.Units.Angle thetaF = frontWheel.angle "Front wheel angle relative to the front frame";
  output Bicycle.Units.Angle beta = hip.angle "Lean angle beta of the upper body relative to the rear frame, positive leaning right";
  output Bicycle.Units.AngularVelocity u_phi = ground.u_phi "Roll rate (independent speed)";
  output Bicycle.Units.AngularVelocity u_delta = steer.omega "Steer rate (independent speed)";
  output Bicycle.Units.AngularVelocity u_R = rearWheel.spin "Rear wheel rate relative to the rear frame (independent speed; negative rolling forward)";
  output Bicycle.Units.AngularVelocity u_beta = hip.omega "Lean rate of the upper body (independent speed)";
  output Bicycle.Units.AngularVelocity u_psi = ground.u_psi "Yaw rate (dependent speed)";
  output Bicycle.Units.AngularVelocity u_theta = ground.u_theta "Pitch rate (dependent speed)";
  output Bicycle.Units.AngularVelocity u_F = ground.u_F "Front wheel rate relative to the front frame (dependent speed)";
  output Bicycle.Units.AngularAcceleration u_psi_dot = ground.u_psi_dot "Time derivative of u_psi";
  output Bicycle.Units.AngularAcceleration u_theta_dot = ground.u_theta_dot "Time derivative of u_theta";
  output Bicycle.Units.AngularAcceleration u_F_dot = ground.u_F_dot "Time derivative of u_F";
  output Bicycle.Units.Velocity v = ground.v "Forward speed of the rear contact point (velocity along the heading)";
  output Bicycle.Units.Energy E = ground.E "Total energy: kinetic + potential (gravity, zero at the ground, and the hip spring)";
  output Bicycle.Units.Length residual = ground.residual "Holonomic constraint residual: height of the front contact point above the ground (should be 0)";
  Bicycle.Mechanics.Ground ground(n = n, g = g, x0 = x0, y0 = y0, psi0 = psi0, phi0 = phi0, u_phi0 = u_phi0, theta_guess = theta_guess) "Flat ground: the rear frame's attitude and position, rolling constraints, Kane's equations"
    annotation(Placement(transformation(extent = {{-160, -110}, {160, -70}})));
  replaceable Bicycle.Wheels.Torus rearWheel(t = tR, n = n, k = 6, r = rR, m = mR, Ixx = IRxx, Iyy = IRyy, angle0 = thetaR0, spin0 = u_R0) constrainedby Bicycle.Wheels.PartialWheel(n = n, k = 6, r = rR, m = mR, Ixx = IRxx, Iyy = IRyy, angle0 = thetaR0, spin0 = u_R0) "Rear wheel R (spin angle thetaR, coordinate 6)"
    annotation(Placement(transformation(extent = {{-130, -55}, {-70, 5}})));
  Bicycle.Mechanics.Frames.RearFrame rearFrame(n = n, w = w, c = c, rR = rR, xB = xB, zB = zB, mB = mB, IBxx = IBxx, IBxz = IBxz, IByy = IByy, IBzz = IBzz) "Rear frame B without the rider's upper body"
    annotation(Placement(transformation(extent = {{-80, 20}, {-40, 60}})));
  Bicycle.Mechanics.Frames.SteerAxis steer(n = n, k = 5, lam = lam, angle0 = delta0, omega0 = u_delta0) "Steer axis (steer angle delta, coordinate 5)"
    annotation(Placement(transformation(extent = {{-10, 20}, {30, 60}})));
  Bicycle.Mechanics.Frames.FrontFrame frontFrame(n = n, w = w, c = c, rF = rF, xH = xH, zH = zH, mH = mH, IHxx = IHxx, IHxz = IHxz, IHyy = IHyy, IHzz = IHzz) "Front frame H (fork and handlebar)"
    annotation(Placement(transformation(extent = {{80, 20}, {120, 60}})));
  replaceable Bicycle.Wheels.Torus frontWheel(t = tF, n = n, k = 3, rolling = true, r = rF, m = mF, Ixx = IFxx, Iyy = IFyy, angle0 = thetaF0) constrainedby Bicycle.Wheels.PartialWheel(n = n, k = 3, rolling = true, r = rF, m = mF, Ixx = IFxx, Iyy = IFyy, angle0 = thetaF0) "Front wheel F (spin angle thetaF; its rate is the dependent speed 3)"
    annotation(Placement(transformation(extent = {{70, -55}, {130, 5}})));
  Bicycle.Mechanics.Parts.FixedTranslation toHip(n = n, rx = xU, rz = rR - hU) "Rear axle to the hip hinge axis (xU, hU above the ground)"
    annotation(Placement(transformation(origin = {-100, 90}, extent = {{-20, -20}, {20, 20}}, rotation = 90)));
  replaceable Bicycle.Mechanics.Rider.HipHinge hip(c = kU, d = cU, n = n, k = 7, angle0 = beta0, omega0 = u_beta0) constrainedby Bicycle.Mechanics.Rider.PartialHinge(n = n, k = 7, angle0 = beta0, omega0 = u_beta0) "Hip hinge (lean angle beta, coordinate 7; LockedHinge: the upper body held at its initial lean)"
    annotation(Placement(transformation(extent = {{-120, 130}, {-80, 170}})));
  Bicycle.Mechanics.Rider.UpperBody upperBody(n = n, m = mU, l = lU, Ixx = IUxx, Ixz = IUxz, Iyy = IUyy, Izz = IUzz) "Rider's upper body U"
    annotation(Placement(transformation(extent = {{-120, 190}, {-80, 230}})));
equation
  // The replaceable components repeat their constraining clause's modifiers (which apply to every
  // replacement, MLS 7.3.2) in the declaration: rumoca 0.10 applies only the latter.
  connect(ground.frame_b, rearWheel.hub) annotation(Line(points = {{-150, -70}, {-150, 40}, {-100, 40}, {-100, 5}}, color = {95, 95, 95}, thickness = 0.5));
  connect(ground.frame_b, rearFrame.frame_a) annotation(Line(points = {{-150, -70}, {-150, 40}, {-80, 40}}, color = {95, 95, 95}, thickness = 0.5));
  connect(rearWheel.contact, ground.rearContact) annotation(Line(points = {{-100, -55}, {-100, -70}}, color = {140, 70, 20}, thickness = 0.5));
  connect(rearFrame.frame_b, steer.frame_a) annotation(Line(points = {{-40, 40}, {-10, 40}}, color = {95, 95, 95}, thickness = 0.5));
  connect(steer.frame_b, frontFrame.frame_a) annotation(Line(points = {{30, 40}, {80, 40}}, color = {95, 95, 95}, thickness = 0.5));
  connect(frontFrame.frame_b, frontWheel.hub) annotation(Line(points = {{100, 20}, {100, 5}}, color = {95, 95, 95}, thickness = 0.5));
  connect(frontWheel.contact, ground.frontContact) annotation(Line(points = {{100, -55}, {100, -70}}, color = {140, 70, 20}, thickness = 0.5));
  connect(T_delta, steer.tau_in) annotation(Line(points = {{10, 250}, {10, 64}}, color = {0, 0, 127}));
  connect(T_phi, ground.T_phi) annotation(Line(points = {{-210, -90}, {-165, -90}}, color = {0, 0, 127}));
  connect(ground.frame_b, toHip.frame_a) annotation(Line(points = {{-150, -70}, {-150, 40}, {-100, 40}, {-100, 70}}, color = {95, 95, 95}, thickness = 0.5));
  connect(toHip.frame_b, hip.frame_a) annotation(Line(points = {{-100, 110}, {-100, 130}}, color = {95, 95, 95}, thickness = 0.5));
  connect(hip.frame_b, upperBody.frame_a) annotation(Line(points = {{-100, 170}, {-100, 190}}, color = {95, 95, 95}, thickness = 0.5));
  connect(T_beta, hip.tau_in) annotation(Line(points = {{-210, 142}, {-124, 142}}, color = {0, 0, 127}));
  annotation(
    Diagram(coordinateSystem(extent = {{-200, -120}, {200, 240}})),
    experiment(StartTime = 0, StopTime = 10, Tolerance = 1e-10, Interval = 0.01),
    __Cosim(export = true,
      singular(
        delta(angle_deg = 90, tolerance_deg = 15, description = "the front wheel stands across the rear frame, where the rolling constraints of the two wheels lose rank (near +-90 deg: the exact steer angle moves with lean and pitch)"),
        phi(angle_deg = 90, tolerance_deg = 15, description = "the wheels lie flat on the ground, where their contact points are undefined"))),
    Documentation(info = "<html>
<p>The nonlinear Whipple bicycle of <a href=\"modelica://Bicycle.Bicycles.Whipple\">Whipple</a> with
the rider's upper body U as a fifth body, hinged to the rear frame B about the longitudinal axis
through <code>(xU, 0)</code> at the height <code>hU</code> above the ground (upright bicycle), its
centre of mass <code>lU</code> above the hinge. The hip hinge (the replaceable component <code>hip</code>,
constrained by <a href=\"modelica://Bicycle.Mechanics.Rider.PartialHinge\">PartialHinge</a>) carries the rider's lean torque <code>T_beta</code> (input) and a passive spring <code>kU</code> and
damper <code>cU</code>. The rear frame's parameters <code>mB, xB, zB, IB..</code> are those
<em>without</em> the upper body; the defaults (<code>Data = Bicycle.Records.BenchmarkRider</code>)
split the benchmark's rear frame so that rear frame + upper body upright is the benchmark's rear
frame (parallel-axis theorem).</p>
<p>Components: rear wheel R, rear frame B, steer axis, front frame H, front wheel F (as in
<code>Whipple</code>), the translation from the rear axle to the hip, the hinge and the upper body;
the hinge owns the lean angle <code>beta</code> of the upper body relative to the rear frame and
its rate <code>u_beta</code>, a fourth independent speed (coordinate 7); nothing else differs from
<code>Whipple</code> but <code>n = 7</code>.</p>
<p>States: <code>x, y, psi, phi, theta, delta, thetaR, thetaF, beta</code> and <code>u_phi, u_delta,
u_R, u_beta</code>; inputs: steer torque <code>T_delta</code>, roll torque <code>T_phi</code>, lean
torque <code>T_beta</code>; outputs as in <code>Whipple</code>, the energy <code>E</code> including the
hinge spring. Signs are Meijaard's (x forward, y right, z down); <code>beta</code> is positive
leaning the upper body to the right relative to the rear frame.</p>
<p>Variants: <code>extends WhippleRider(redeclare Bicycle.Mechanics.Rider.LockedHinge hip)</code> fixes the
upper body to the rear frame (the bicycle with the rider rigidly attached); the wheels are replaceable
as in <code>Whipple</code> (<code>redeclare Bicycle.Wheels.KnifeEdge rearWheel</code>, ...). The
equations equal those of the flat model generated by sympy (<code>tests/oracle</code>,
<code>tests/test_component_rider.py</code>).</p>
</html>"));
end WhippleRider;
