within Bicycle.Bicycles;
model Whipple "Nonlinear Whipple bicycle (Meijaard et al. 2007): rear wheel, rear frame, steer axis, front frame, front wheel rolling on flat ground"
  extends Bicycle.Icons.Bike;
  extends Bicycle.Bicycles.PartialWhippleParameters(
    w = Data.w, c = Data.c, lam = Data.lam, g = Data.g,
    rR = Data.rR, mR = Data.mR, IRxx = Data.IRxx, IRyy = Data.IRyy,
    xB = Data.xB, zB = Data.zB, mB = Data.mB,
    IBxx = Data.IBxx, IBxz = Data.IBxz, IByy = Data.IByy, IBzz = Data.IBzz,
    xH = Data.xH, zH = Data.zH, mH = Data.mH,
    IHxx = Data.IHxx, IHxz = Data.IHxz, IHyy = Data.IHyy, IHzz = Data.IHzz,
    rF = Data.rF, mF = Data.mF, IFxx = Data.IFxx, IFyy = Data.IFyy);
  replaceable package Data = Bicycle.Records.Benchmark constrainedby Bicycle.Records.PartialWhipple "Parameter set (the values of the parameters bound in the extends clause)";
  constant Integer n = 6 "Number of generalized speeds: 1 to 3 dependent (yaw, pitch, front wheel), 4 roll, 5 steer, 6 rear wheel";
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
  parameter Bicycle.Units.Length tF(min = 0) = 0 "Front tyre crown radius tF (toroidal wheel; 0: knife edge)";
  Bicycle.Interfaces.RealInput T_delta(final quantity = "Torque", final unit = "N.m") "Steer torque T_delta between rear frame and front frame, positive tending to steer right"
    annotation(Placement(transformation(origin = {10, 110}, extent = {{-10, -10}, {10, 10}}, rotation = -90), iconTransformation(extent = {{-140, 20}, {-100, 60}})));
  Bicycle.Interfaces.RealInput T_phi(final quantity = "Torque", final unit = "N.m") "Roll torque T_phi on the rear frame about the (horizontal) roll axis, positive tending to lean right (disturbance)"
    annotation(Placement(transformation(extent = {{-220, -100}, {-200, -80}}), iconTransformation(extent = {{-140, -60}, {-100, -20}})));
  output Bicycle.Units.Position x = ground.x "x coordinate (forward at yaw 0) of the rear contact point";
  output Bicycle.Units.Position y = ground.y "y coordinate (right at yaw 0) of the rear contact point: lateral position";
  output Bicycle.Units.Angle psi = ground.psi "Yaw angle psi of the rear frame, positive turning right";
  output Bicycle.Units.Angle phi = ground.phi "Roll angle phi of the rear frame, positive leaning right";
  output Bicycle.Units.Angle theta = ground.theta "Pitch angle theta of the rear frame, positive nose up (0: upright, zero steer)";
  output Bicycle.Units.Angle delta = steer.angle "Steer angle delta, positive steering right";
  output Bicycle.Units.Angle thetaR = rearWheel.angle "Rear wheel angle relative to the rear frame";
  output Bicycle.Units.Angle thetaF = frontWheel.angle "Front wheel angle relative to the front frame";
  output Bicycle.Units.AngularVelocity u_phi = ground.u_phi "Roll rate (independent speed)";
  output Bicycle.Units.AngularVelocity u_delta = steer.omega "Steer rate (independent speed)";
  output Bicycle.Units.AngularVelocity u_R = rearWheel.spin "Rear wheel rate relative to the rear frame (independent speed; negative rolling forward)";
  output Bicycle.Units.AngularVelocity u_psi = ground.u_psi "Yaw rate (dependent speed)";
  output Bicycle.Units.AngularVelocity u_theta = ground.u_theta "Pitch rate (dependent speed)";
  output Bicycle.Units.AngularVelocity u_F = ground.u_F "Front wheel rate relative to the front frame (dependent speed)";
  output Bicycle.Units.AngularAcceleration u_psi_dot = ground.u_psi_dot "Time derivative of u_psi";
  output Bicycle.Units.AngularAcceleration u_theta_dot = ground.u_theta_dot "Time derivative of u_theta";
  output Bicycle.Units.AngularAcceleration u_F_dot = ground.u_F_dot "Time derivative of u_F";
  output Bicycle.Units.Velocity v = ground.v "Forward speed of the rear contact point (velocity along the heading)";
  output Bicycle.Units.Energy E = ground.E "Total energy: kinetic + potential (gravity, zero at the ground)";
  output Bicycle.Units.Length residual = ground.residual "Holonomic constraint residual: height of the front contact point above the ground (should be 0)";
  Bicycle.Mechanics.Ground ground(n = n, g = g, x0 = x0, y0 = y0, psi0 = psi0, phi0 = phi0, u_phi0 = u_phi0, theta_guess = theta_guess) "Flat ground: the rear frame's attitude and position, rolling constraints, Kane's equations"
    annotation(Placement(transformation(extent = {{-160, -110}, {160, -70}})));
  replaceable Bicycle.Wheels.Torus rearWheel(t = tR, n = n, k = 6, r = rR, m = mR, Ixx = IRxx, Iyy = IRyy, angle0 = thetaR0, spin0 = u_R0) constrainedby Bicycle.Wheels.PartialWheel(n = n, k = 6, r = rR, m = mR, Ixx = IRxx, Iyy = IRyy, angle0 = thetaR0, spin0 = u_R0) "Rear wheel R (spin angle thetaR, coordinate 6)"
    annotation(Placement(transformation(extent = {{-130, -55}, {-70, 5}})));
  Bicycle.Mechanics.Frames.RearFrame rearFrame(n = n, w = w, c = c, rR = rR, xB = xB, zB = zB, mB = mB, IBxx = IBxx, IBxz = IBxz, IByy = IByy, IBzz = IBzz) "Rear frame B with the rider"
    annotation(Placement(transformation(extent = {{-80, 20}, {-40, 60}})));
  Bicycle.Mechanics.Frames.SteerAxis steer(n = n, k = 5, lam = lam, angle0 = delta0, omega0 = u_delta0) "Steer axis (steer angle delta, coordinate 5)"
    annotation(Placement(transformation(extent = {{-10, 20}, {30, 60}})));
  Bicycle.Mechanics.Frames.FrontFrame frontFrame(n = n, w = w, c = c, rF = rF, xH = xH, zH = zH, mH = mH, IHxx = IHxx, IHxz = IHxz, IHyy = IHyy, IHzz = IHzz) "Front frame H (fork and handlebar)"
    annotation(Placement(transformation(extent = {{80, 20}, {120, 60}})));
  replaceable Bicycle.Wheels.Torus frontWheel(t = tF, n = n, k = 3, rolling = true, r = rF, m = mF, Ixx = IFxx, Iyy = IFyy, angle0 = thetaF0) constrainedby Bicycle.Wheels.PartialWheel(n = n, k = 3, rolling = true, r = rF, m = mF, Ixx = IFxx, Iyy = IFyy, angle0 = thetaF0) "Front wheel F (spin angle thetaF; its rate is the dependent speed 3)"
    annotation(Placement(transformation(extent = {{70, -55}, {130, 5}})));
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
  connect(T_delta, steer.tau_in) annotation(Line(points = {{10, 110}, {10, 64}}, color = {0, 0, 127}));
  connect(T_phi, ground.T_phi) annotation(Line(points = {{-210, -90}, {-165, -90}}, color = {0, 0, 127}));
  annotation(
    Diagram(coordinateSystem(extent = {{-200, -120}, {200, 100}})),
    experiment(StartTime = 0, StopTime = 10, Tolerance = 1e-10, Interval = 0.01),
    __Cosim(export = true,
      singular(
        delta(angle_deg = 90, tolerance_deg = 15, description = "the front wheel stands across the rear frame, where the rolling constraints of the two wheels lose rank (near +-90 deg: the exact steer angle moves with lean and pitch)"),
        phi(angle_deg = 90, tolerance_deg = 15, description = "the wheels lie flat on the ground, where their contact points are undefined"))),
    Documentation(info = "<html>
<p>The nonlinear Whipple bicycle assembled from components: rear wheel R, rear frame B (rider
rigidly attached), steer axis, front frame H (fork and handlebar), front wheel F, with the
parameters of Meijaard et al. (2007), Table 1 (defaults: the data set <code>Data</code>) and toroidal
wheels with crown radii <code>tR</code>, <code>tF</code> (0: knife edge). Rolling without slip on flat
ground; the equations of motion are Kane's, stated by <a href=\"modelica://Bicycle.Mechanics.Ground\">Ground</a>
on the sum of the bodies' contributions. Each joint owns its coordinate: the ground the rear
frame's position and attitude, the steer axis the steer angle, each wheel its spin angle; the model
names them (<code>delta = steer.angle</code>, ...), and says the number of generalized speeds
<code>n</code> once.</p>
<p>States: rear contact point <code>x, y</code>; yaw <code>psi</code>, roll <code>phi</code>, pitch
<code>theta</code>, steer <code>delta</code>, wheel angles <code>thetaR, thetaF</code>; the independent
speeds <code>u_phi, u_delta, u_R</code>. The dependent speeds <code>u_psi, u_theta, u_F</code> and their
rates are outputs, with the forward speed <code>v</code>, the total energy <code>E</code> and the
holonomic constraint residual (height of the front contact point). Inputs: the steer torque
<code>T_delta</code> and a roll torque <code>T_phi</code> on the rear frame.</p>
<p>Signs are Meijaard's: x forward, y right, z down; roll positive leaning right, steer positive to
the right, yaw positive turning right, pitch positive nose up; wheel rates are negative when rolling
forward (forward speed <code>v = -u_R rR</code> upright).</p>
<p>The wheels are replaceable components constrained by <code>Bicycle.Wheels.PartialWheel</code>
(whose modifiers, given in the constraining clause, apply to every replacement), e.g.
<code>extends Whipple(redeclare Bicycle.Wheels.Roller rearWheel(R = 0.4))</code> or
<code>redeclare Bicycle.Wheels.KnifeEdge frontWheel</code>. The equations equal those of the flat model
generated by sympy (<code>tests/oracle</code>, <code>tests/test_component_bicycle.py</code>).</p>
</html>"));
end Whipple;
