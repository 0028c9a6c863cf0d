#include <onnx/checker.h>
#include <onnx/onnx_pb.h>

#include <Eigen/Core>
#include <map>
#include <set>

#include "core/atomic_file.h"
#include "core/error.h"
#include "kernels/nn/nn_onnx.h"

namespace pensight::kernels {
namespace {

constexpr int kOpset = 17;

class Writer {
 public:
  Writer(const Graph& g, const OnnxExportOptions& o) : g_(g), opt_(o) {}

  std::string run() {
    onnx::ModelProto model;
    model.set_ir_version(8);
    model.set_producer_name(opt_.producer);
    auto* opset = model.add_opset_import();
    opset->set_domain("");
    opset->set_version(kOpset);
    graph_ = model.mutable_graph();
    graph_->set_name("pensight");
    for (int v : g_.inputs()) value_info(graph_->add_input(), v);
    for (const Node& n : g_.nodes()) node(n);
    for (int v : g_.outputs()) value_info(graph_->add_output(), v);
    std::string bytes;
    if (!model.SerializeToString(&bytes)) throw Error("export_onnx: protobuf serialisation failed");
    return bytes;
  }

 private:
  // ONNX tensor name of a value: its own name, made unique (ONNX graphs are SSA; imported node
  // names need not be unique).
  const std::string& tensor_name(int v) {
    auto it = names_.find(v);
    if (it != names_.end()) return it->second;
    std::string nm = g_.value(v).name;
    for (int k = 1; used_.count(nm); ++k) nm = g_.value(v).name + "_" + std::to_string(k);
    used_.insert(nm);
    return names_[v] = nm;
  }

  std::string name(int v) {
    const Value& val = g_.value(v);
    const std::string vname = tensor_name(v);
    if (val.is_constant && !emitted_[v]) {
      emitted_[v] = true;
      if (opt_.fp16_weights && val.data.size() > 1) {
        auto* t = graph_->add_initializer();
        t->set_name(vname + "_fp16");
        for (int64_t d : val.shape) t->add_dims(d);
        t->set_data_type(onnx::TensorProto::FLOAT16);
        std::string raw(val.data.size() * 2, '\0');
        for (size_t i = 0; i < val.data.size(); ++i) {
          const uint16_t h = Eigen::half(val.data[i]).x;
          std::memcpy(&raw[2 * i], &h, 2);
        }
        t->set_raw_data(raw);
        auto* cast = graph_->add_node();
        cast->set_op_type("Cast");
        cast->set_name(vname + "_cast");
        cast->add_input(vname + "_fp16");
        cast->add_output(vname);
        attr_int(cast, "to", onnx::TensorProto::FLOAT);
      } else {
        auto* t = graph_->add_initializer();
        t->set_name(vname);
        for (int64_t d : val.shape) t->add_dims(d);
        t->set_data_type(onnx::TensorProto::FLOAT);
        t->set_raw_data(
            std::string(reinterpret_cast<const char*>(val.data.data()), val.data.size() * 4));
      }
    }
    return vname;
  }
  std::string ints_init(const std::string& nm, const std::vector<int64_t>& v) {
    auto* t = graph_->add_initializer();
    t->set_name(nm);
    t->add_dims(static_cast<int64_t>(v.size()));
    t->set_data_type(onnx::TensorProto::INT64);
    for (int64_t x : v) t->add_int64_data(x);
    return nm;
  }
  std::string float_init(const std::string& nm, float v) {
    auto* t = graph_->add_initializer();
    t->set_name(nm);
    t->set_data_type(onnx::TensorProto::FLOAT);
    t->add_float_data(v);
    return nm;
  }
  void value_info(onnx::ValueInfoProto* vi, int v) {
    vi->set_name(tensor_name(v));
    auto* tt = vi->mutable_type()->mutable_tensor_type();
    tt->set_elem_type(onnx::TensorProto::FLOAT);
    for (int64_t d : g_.value(v).shape) tt->mutable_shape()->add_dim()->set_dim_value(d);
  }
  static void attr_int(onnx::NodeProto* n, const char* nm, int64_t v) {
    auto* a = n->add_attribute();
    a->set_name(nm);
    a->set_type(onnx::AttributeProto::INT);
    a->set_i(v);
  }
  static void attr_float(onnx::NodeProto* n, const char* nm, float v) {
    auto* a = n->add_attribute();
    a->set_name(nm);
    a->set_type(onnx::AttributeProto::FLOAT);
    a->set_f(v);
  }
  static void attr_str(onnx::NodeProto* n, const char* nm, const std::string& v) {
    auto* a = n->add_attribute();
    a->set_name(nm);
    a->set_type(onnx::AttributeProto::STRING);
    a->set_s(v);
  }
  template <class C>
  static void attr_ints(onnx::NodeProto* n, const char* nm, const C& v) {
    auto* a = n->add_attribute();
    a->set_name(nm);
    a->set_type(onnx::AttributeProto::INTS);
    for (auto x : v) a->add_ints(x);
  }

  void node(const Node& n) {
    std::vector<std::string> inputs;  // named first: an fp16 weight's Cast must precede its reader
    for (int v : n.inputs) inputs.push_back(name(v));
    auto* p = graph_->add_node();
    p->set_name(n.name);
    p->set_op_type(to_string(n.op));
    for (const std::string& in : inputs) p->add_input(in);
    p->add_output(tensor_name(n.output));
    const Attrs& a = n.attrs;
    switch (n.op) {
      case Op::kConv:
      case Op::kConvTranspose:
        attr_ints(p, "kernel_shape", a.kernel);
        attr_ints(p, "strides", a.stride);
        attr_ints(p, "dilations", a.dilation);
        attr_ints(p, "pads", a.pads);
        attr_int(p, "group", a.group);
        if (n.op == Op::kConvTranspose) attr_ints(p, "output_padding", a.output_padding);
        break;
      case Op::kClip:
        p->add_input(float_init(n.name + "_min", a.alpha));
        p->add_input(float_init(n.name + "_max", a.beta));
        break;
      case Op::kLeakyRelu:
        attr_float(p, "alpha", a.alpha);
        break;
      case Op::kConcat:
      case Op::kSoftmax:
      case Op::kFlatten:
        attr_int(p, "axis", a.axis);
        break;
      case Op::kResize: {
        const Dims& x = g_.value(n.inputs[0]).shape;
        p->add_input("");
        p->add_input("");
        p->add_input(ints_init(n.name + "_sizes", {x[0], x[1], a.sizes[0], a.sizes[1]}));
        if (a.resize == ResizeMode::kNearest) {
          attr_str(p, "mode", "nearest");
          attr_str(p, "coordinate_transformation_mode", "asymmetric");
          attr_str(p, "nearest_mode", "floor");
        } else {
          attr_str(p, "mode", "linear");
          attr_str(p, "coordinate_transformation_mode",
                   a.resize == ResizeMode::kLinearAlignCorners ? "align_corners" : "half_pixel");
        }
        break;
      }
      case Op::kMaxPool:
      case Op::kAveragePool:
        attr_ints(p, "kernel_shape", a.kernel);
        attr_ints(p, "strides", a.stride);
        attr_ints(p, "pads", a.pads);
        if (n.op == Op::kAveragePool) attr_int(p, "count_include_pad", a.count_include_pad ? 1 : 0);
        break;
      case Op::kGemm:
        attr_float(p, "alpha", a.alpha);
        attr_float(p, "beta", a.beta);
        attr_int(p, "transA", a.trans_a ? 1 : 0);
        attr_int(p, "transB", a.trans_b ? 1 : 0);
        break;
      case Op::kTranspose:
        attr_ints(p, "perm", a.ints);
        break;
      case Op::kReshape:
        p->add_input(ints_init(n.name + "_shape", a.ints));
        break;
      case Op::kSlice: {
        const Dims& out = g_.value(n.output).shape;
        std::vector<int64_t> ends, axes;
        for (size_t i = 0; i < out.size(); ++i) {
          ends.push_back(a.starts[i] + (out[i] - 1) * a.steps[i] + 1);
          axes.push_back(static_cast<int64_t>(i));
        }
        p->add_input(ints_init(n.name + "_starts", a.starts));
        p->add_input(ints_init(n.name + "_ends", ends));
        p->add_input(ints_init(n.name + "_axes", axes));
        p->add_input(ints_init(n.name + "_steps", a.steps));
        break;
      }
      case Op::kReduceMean:
        attr_ints(p, "axes", a.axes);
        attr_int(p, "keepdims", a.keepdims ? 1 : 0);
        break;
      case Op::kLayerNorm:
        attr_int(p, "axis", a.axis);
        attr_float(p, "epsilon", a.epsilon);
        break;
      default:
        break;
    }
  }

  const Graph& g_;
  const OnnxExportOptions& opt_;
  onnx::GraphProto* graph_ = nullptr;
  std::map<int, bool> emitted_;
  std::map<int, std::string> names_;
  std::set<std::string> used_;
};

}  // namespace

std::string export_onnx_bytes(const Graph& graph, const OnnxExportOptions& options) {
  return Writer(graph, options).run();
}

void export_onnx(const Graph& graph, const std::filesystem::path& file,
                 const OnnxExportOptions& options) {
  const std::string bytes = export_onnx_bytes(graph, options);
  try {
    write_file_atomically(file, bytes);
  } catch (const Error&) {
    throw Error("export_onnx: cannot write '" + file.string() +
                "' (check the folder exists and is writable)");
  }
}

std::string opencv_dnn_compatible(const std::string& onnx_bytes) {
  onnx::ModelProto m;
  if (!m.ParseFromString(onnx_bytes))
    throw Error("opencv_dnn_compatible: the bytes are not an ONNX model");
  std::map<std::string, float> scalars;
  for (const auto& t : m.graph().initializer()) {
    if (t.float_data_size() == 1) scalars[t.name()] = t.float_data(0);
  }
  for (auto& n : *m.mutable_graph()->mutable_node()) {
    if (n.op_type() != "Clip" || n.input_size() != 3) continue;
    for (int i : {1, 2}) {
      auto it = scalars.find(n.input(i));
      if (it == scalars.end())
        throw Error("opencv_dnn_compatible: Clip '" + n.name() + "' has a non-constant bound");
      auto* a = n.add_attribute();
      a->set_name(i == 1 ? "min" : "max");
      a->set_type(onnx::AttributeProto::FLOAT);
      a->set_f(it->second);
    }
    n.mutable_input()->DeleteSubrange(1, 2);
  }
  std::string out;
  m.SerializeToString(&out);
  return out;
}

void check_onnx_bytes(const std::string& bytes) {
  onnx::ModelProto model;
  if (!model.ParseFromString(bytes))
    throw Error("ONNX checker: the bytes are not an ONNX ModelProto");
  try {
    onnx::checker::check_model(model);
  } catch (const std::exception& e) {
    throw Error(std::string("ONNX checker: ") + e.what());
  }
}

}  // namespace pensight::kernels
