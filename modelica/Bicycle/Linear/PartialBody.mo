within Bicycle.Linear;
partial model PartialBody "Rigid body of the linearized bicycle: its mass properties and its parts of M, C1, K0, K2 (Meijaard 2007, Appendix A)"
  // Geometry and operating point of the bicycle the body belongs to
  parameter Bicycle.Units.Length w(min = 1e-6) "Wheelbase w";
  parameter Bicycle.Units.Length c "Trail c (positive: front contact point behind the steer axis)";
  parameter Bicycle.Units.Angle lam(min = -1.5707963267948966, max = 1.5707963267948966) "Steer-axis tilt lam from the vertical (pi/2 - head angle)";
  parameter Bicycle.Units.Acceleration g(min = 0) "Gravitational acceleration g";
  parameter Bicycle.Units.Velocity v "Forward speed v of the rear contact point";
  // Mass properties (bound by the concrete bodies)
  parameter Bicycle.Units.Mass m(min = 0) "Mass";
  parameter Bicycle.Units.Position x "Centre of mass: x coordinate (forward from the rear contact point)";
  parameter Bicycle.Units.Position z "Centre of mass: z coordinate (down; negative above the ground)";
  parameter Bicycle.Units.MomentOfInertia Ixx(min = 0) "Inertia-tensor element xx about the centre of mass";
  parameter Bicycle.Units.MomentOfInertia Ixz "Inertia-tensor element xz about the centre of mass (-integral(x z dm))";
  parameter Bicycle.Units.MomentOfInertia Izz(min = 0) "Inertia-tensor element zz about the centre of mass";
  parameter Bicycle.Units.FirstMomentOfMass S "Gyrostatic coefficient: spin angular momentum per forward speed (Iyy/r of a wheel, 0 for a frame)";
  // Moments about the rear contact point (parallel-axis theorem), the body's parts of A1-A6
  final parameter Bicycle.Units.FirstMomentOfMass mx = m*x "First moment of mass m*x (part of mT xT)";
  final parameter Bicycle.Units.FirstMomentOfMass mz = m*z "First moment of mass m*z (part of mT zT)";
  final parameter Bicycle.Units.MomentOfInertia Jxx = Ixx + m*z^2 "Inertia-tensor element xx about the rear contact point (part of ITxx)";
  final parameter Bicycle.Units.MomentOfInertia Jxz = Ixz - m*x*z "Inertia-tensor element xz about the rear contact point (part of ITxz)";
  final parameter Bicycle.Units.MomentOfInertia Jzz = Izz + m*x^2 "Inertia-tensor element zz about the rear contact point (part of ITzz)";
  final parameter Bicycle.Units.DimensionlessRatio mu = c/w*cos(lam) "Trail factor mu = c cos(lam)/w (A16)";
  // The body's parts of the matrices of eq (24) (A20-A26), bound by PartialRearBody or PartialFrontBody;
  // C1_11 = K2_11 = K2_21 = 0, M and K0 are symmetric
  parameter Bicycle.Units.MomentOfInertia M11 "Part of the mass matrix M, element (phi, phi)";
  parameter Bicycle.Units.MomentOfInertia M12 "Part of the mass matrix M, element (phi, delta) = (delta, phi)";
  parameter Bicycle.Units.MomentOfInertia M22 "Part of the mass matrix M, element (delta, delta)";
  parameter Bicycle.Units.FirstMomentOfMass K0_11 "Part of the gravity stiffness K0, element (phi, phi)";
  parameter Bicycle.Units.FirstMomentOfMass K0_12 "Part of the gravity stiffness K0, element (phi, delta) = (delta, phi)";
  parameter Bicycle.Units.FirstMomentOfMass K0_22 "Part of the gravity stiffness K0, element (delta, delta)";
  parameter Bicycle.Units.MassCoefficient K2_12 "Part of the velocity-squared stiffness K2, element (phi, delta)";
  parameter Bicycle.Units.MassCoefficient K2_22 "Part of the velocity-squared stiffness K2, element (delta, delta)";
  parameter Bicycle.Units.FirstMomentOfMass C1_12 "Part of the velocity-proportional matrix C1, element (phi, delta)";
  parameter Bicycle.Units.FirstMomentOfMass C1_21 "Part of the velocity-proportional matrix C1, element (delta, phi)";
  parameter Bicycle.Units.FirstMomentOfMass C1_22 "Part of the velocity-proportional matrix C1, element (delta, delta)";
  Bicycle.Linear.RollSteer_a frame "Roll and steer coordinates; the body's generalized force, inertia terms included, goes out through it"
    annotation(Placement(transformation(extent = {{-16, -116}, {16, -84}})));
equation
  // d'Alembert: the generalized force through the connector balances the body's part of eq (24), inertia terms included
  frame.Q_phi = M11*frame.phi_ddot + M12*frame.delta_ddot + v*C1_12*frame.delta_dot + g*K0_11*frame.phi + (g*K0_12 + v^2*K2_12)*frame.delta;
  frame.Q_delta = M12*frame.phi_ddot + M22*frame.delta_ddot + v*(C1_21*frame.phi_dot + C1_22*frame.delta_dot) + g*K0_12*frame.phi + (g*K0_22 + v^2*K2_22)*frame.delta;
  annotation(Documentation(info = "<html>
<p>A rigid body symmetric about the bicycle's x-z plane, in the axes of Meijaard et al. (2007):
x forward, y right, z down, origin at the rear contact point of the upright bicycle with zero steer.
The whole bicycle's M, C1, K0 and K2 (eq (24)) are linear in the totals of Appendix A (mT xT, mT zT,
ITxx, ITxz, ITzz, mA uA, IAll, IAlx, IAlz, SR, SF), and each total is a sum over the bodies; so the
body's part of every matrix element is the element's formula applied to the body's own moments.
The parts are bound by <a href=\"modelica://Bicycle.Linear.PartialRearBody\">PartialRearBody</a>
(a body that does not turn about the steer axis) and
<a href=\"modelica://Bicycle.Linear.PartialFrontBody\">PartialFrontBody</a> (a body of the front
assembly).</p>
<p>Through <code>frame</code> (<a href=\"modelica://Bicycle.Linear.RollSteer_a\">RollSteer_a</a>)
the body receives the coordinates q = [phi; delta] and speeds q' as inputs and shares the
accelerations q'' with the other components. It delivers the generalized force that keeps it in
d'Alembert equilibrium, its inertia terms included (flows positive into the body):</p>
<pre>  Q = M_i q'' + v C1_i q' + (g K0_i + v^2 K2_i) q</pre>
<p>The mass-matrix part M_i enters the equation rather than the connector: a flow for each
element of M would make the connector unbalanced (more flows than potentials). The parameters
M11 ... C1_22 stay declared, so that an assembly can report the summed matrices.</p>
</html>"));
end PartialBody;
