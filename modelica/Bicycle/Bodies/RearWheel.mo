within Bicycle.Bodies;
model RearWheel "Rear wheel R: axisymmetric knife-edge wheel with its centre above the origin (Meijaard 2007, Table 1)"
  extends Bicycle.Bodies.Wheel(r = 0.3, m = 2, Ixx = 0.0603, Iyy = 0.12);
  final parameter Bicycle.Units.MomentOfInertia Jzz = Ixx "Inertia-tensor element zz about the rear contact point (= Ixx: the centre lies on the z axis)";
  annotation(Documentation(info = "<html>
<p>Rear wheel with its centre at x = 0, z = -r, straight above the rear contact point (the origin).
Its first moment m*x and its inertia-tensor element Jxz about the origin are therefore zero and not
declared. Defaults: the benchmark bicycle of Meijaard et al. (2007) (rR, mR, IRxx, IRyy).</p>
</html>"));
end RearWheel;
